/*
 * expm1 and log1p from exp and log, for C libraries without them (avr-libc
 * has neither; PDT_MATH_FALLBACK in pdt_config.h selects these). Both use
 * Kahan's correction: the rounding of u = e^x (or u = 1 + x) is undone by
 * the exact ratio x / log(u) (or x / (u - 1)), so near 0, where exp(x) - 1
 * and log(1 + x) cancel, the result keeps a few ulps instead of losing
 * every digit. Always compiled, so that the host tests check them in every
 * build; unreferenced, the linker leaves them out.
 */
#include "pdt_internal.h"

pdt_real_t pdt_math_expm1(pdt_real_t x)
{
    const pdt_real_t u = pdt_exp(x);
    if (u == PDT_R(1.0)) {
        return x; /* |x| below half an ulp of 1: e^x - 1 = x to rounding */
    }
    const pdt_real_t um1 = u - PDT_R(1.0);
    if (um1 == PDT_R(-1.0) || !(u <= PDT_REAL_MAX)) {
        return um1; /* -1 far below 0, the overflow (or NaN) as exp gave it */
    }
    return um1 * x / pdt_log(u);
}

pdt_real_t pdt_math_log1p(pdt_real_t x)
{
    const pdt_real_t u = PDT_R(1.0) + x;
    if (u == PDT_R(1.0)) {
        return x; /* log(1 + x) = x to rounding */
    }
    if (!(u <= PDT_REAL_MAX)) {
        return pdt_log(u); /* +inf and NaN as log gives them */
    }
    return pdt_log(u) * x / (u - PDT_R(1.0));
}
