/*
 * Small dense linear algebra shared inside the library; see pdt_linalg.h.
 */
#include "pdt_linalg.h"

#include "pdt_internal.h"

bool pdt_chol_solve(pdt_real_t *A, size_t stride, uint32_t n, pdt_real_t rel, pdt_real_t *x)
{
    for (uint32_t j = 0; j < n; j++) {
        pdt_real_t *aj = &A[j * stride];
        const pdt_real_t least = rel > PDT_R(0.0) ? rel * aj[j] : PDT_R(0.0);
        pdt_real_t s = aj[j];
        for (uint32_t k = 0; k < j; k++) {
            s -= aj[k] * aj[k];
        }
        if (!(s > least)) {
            return false;
        }
        aj[j] = pdt_sqrt(s);
        for (uint32_t i = j + 1u; i < n; i++) {
            pdt_real_t *ai = &A[i * stride];
            pdt_real_t t = ai[j];
            for (uint32_t k = 0; k < j; k++) {
                t -= ai[k] * aj[k];
            }
            ai[j] = t / aj[j];
        }
    }
    for (uint32_t i = 0; i < n; i++) {
        const pdt_real_t *ai = &A[i * stride];
        pdt_real_t t = x[i];
        for (uint32_t k = 0; k < i; k++) {
            t -= ai[k] * x[k];
        }
        x[i] = t / ai[i];
    }
    for (uint32_t ii = n; ii-- > 0u;) {
        pdt_real_t t = x[ii];
        for (uint32_t k = ii + 1u; k < n; k++) {
            t -= A[k * stride + ii] * x[k];
        }
        x[ii] = t / A[ii * stride + ii];
    }
    return true;
}
