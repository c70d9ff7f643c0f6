/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Included in every translation unit of the ARM64 FMUs (-include): binds the libm functions whose
 * symbol versions glibc renewed (logf 2.27; exp, exp2, log, log2, pow 2.29; hypot 2.35) to the ARM64
 * port's first version, GLIBC_2.17, which every glibc still provides, so that the FMU loads on any
 * glibc >= 2.17. (x86-64 links prebuilt LAPACK objects and redirects them with glibc_compat.c.)
 * A function a unit does not call is not referenced by its directive.
 */
#if defined(__aarch64__) && defined(__linux__)
__asm__(".symver exp,exp@GLIBC_2.17");
__asm__(".symver exp2,exp2@GLIBC_2.17");
__asm__(".symver log,log@GLIBC_2.17");
__asm__(".symver log2,log2@GLIBC_2.17");
__asm__(".symver pow,pow@GLIBC_2.17");
__asm__(".symver logf,logf@GLIBC_2.17");
__asm__(".symver hypot,hypot@GLIBC_2.17");
__asm__(".symver expf,expf@GLIBC_2.17");
__asm__(".symver exp2f,exp2f@GLIBC_2.17");
__asm__(".symver log2f,log2f@GLIBC_2.17");
__asm__(".symver powf,powf@GLIBC_2.17");
#endif
