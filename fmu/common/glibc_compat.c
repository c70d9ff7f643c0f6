/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Keeps the FMU loadable on old Linux distributions: glibc 2.29 gave exp, log, pow, exp2 and log2
 * new symbol versions, which a binary linked here would require. The linker redirects every call
 * (ours and the static LAPACK's) to these wrappers (-Wl,--wrap=NAME), which bind to the baseline
 * x86_64 versions (GLIBC_2.2.5) that every glibc still provides. The wrappers are needed because
 * the static LAPACK's objects are prebuilt; the ARM64 build has no such objects and binds its own
 * calls with glibc_baseline.h instead (lld keeps a --wrap'ed symbol's new version in .dynsym).
 */
#include <stdlib.h> /* defines __GLIBC__ on glibc systems */

#if defined(__x86_64__) && defined(__GLIBC__)
double __exp_compat(double);
double __log_compat(double);
double __pow_compat(double, double);
double __exp2_compat(double);
double __log2_compat(double);
float __logf_compat(float);
double __hypot_compat(double, double);
__asm__(".symver __exp_compat,exp@GLIBC_2.2.5");
__asm__(".symver __log_compat,log@GLIBC_2.2.5");
__asm__(".symver __pow_compat,pow@GLIBC_2.2.5");
__asm__(".symver __exp2_compat,exp2@GLIBC_2.2.5");
__asm__(".symver __log2_compat,log2@GLIBC_2.2.5");
__asm__(".symver __logf_compat,logf@GLIBC_2.2.5");
__asm__(".symver __hypot_compat,hypot@GLIBC_2.2.5");

double __wrap_exp(double x);
double __wrap_log(double x);
double __wrap_pow(double x, double y);
double __wrap_exp2(double x);
double __wrap_log2(double x);
float __wrap_logf(float x);
double __wrap_hypot(double x, double y);

double __wrap_exp(double x) { return __exp_compat(x); }
double __wrap_log(double x) { return __log_compat(x); }
double __wrap_pow(double x, double y) { return __pow_compat(x, y); }
double __wrap_exp2(double x) { return __exp2_compat(x); }
double __wrap_log2(double x) { return __log2_compat(x); }
float __wrap_logf(float x) { return __logf_compat(x); }
double __wrap_hypot(double x, double y) { return __hypot_compat(x, y); }
#else
typedef int okid_glibc_compat_not_needed; /* ISO C wants a non-empty translation unit */
#endif
