/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The two libgfortran string helpers that the static reference LAPACK calls (character arguments
 * such as JOBU = 'O' are compared and concatenated when LAPACK calls ILAENV and XERBLA), so the
 * FMU needs no libgfortran at run time. Semantics as in libgfortran: blank-padded comparison.
 */
#include <stddef.h>
#include <string.h>

int _gfortran_compare_string(size_t len1, const char *s1, size_t len2, const char *s2);
void _gfortran_concat_string(size_t destlen, char *dest, size_t len1, const char *s1, size_t len2, const char *s2);

int _gfortran_compare_string(size_t len1, const char *s1, size_t len2, const char *s2)
{
    const size_t common = len1 < len2 ? len1 : len2;
    const int res = memcmp(s1, s2, common);
    if (res != 0) return res < 0 ? -1 : 1;
    const char *rest = len1 > len2 ? s1 + common : s2 + common;
    const size_t rest_len = len1 > len2 ? len1 - common : len2 - common;
    for (size_t i = 0; i < rest_len; ++i) {
        if (rest[i] != ' ') {
            const int above = (unsigned char)rest[i] > ' ';
            return (len1 > len2) == above ? 1 : -1;
        }
    }
    return 0;
}

void _gfortran_concat_string(size_t destlen, char *dest, size_t len1, const char *s1, size_t len2, const char *s2)
{
    if (len1 >= destlen) {
        memcpy(dest, s1, destlen);
        return;
    }
    memcpy(dest, s1, len1);
    dest += len1;
    destlen -= len1;
    if (len2 >= destlen) {
        memcpy(dest, s2, destlen);
        return;
    }
    memcpy(dest, s2, len2);
    memset(dest + len2, ' ', destlen - len2);
}
