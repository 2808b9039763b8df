/*
 * Small dense linear algebra shared inside the library: the validation's
 * normal equations (up to PDT_VALIDATE_FIR unknowns) and the polish's
 * Newton step (up to three).
 */
#ifndef PDT_LINALG_H
#define PDT_LINALG_H

#include "pdt/pdt_common.h"

/* Solves A x = x (b in, the solution out) for a symmetric n x n A, row i
 * at A[i * stride], by Cholesky in place (A's lower triangle becomes L).
 * False when a pivot is not above rel times its diagonal's first value
 * (rel = 0: not positive): A is then not positive definite enough, and x
 * is left part-way. */
bool pdt_chol_solve(pdt_real_t *A, size_t stride, uint32_t n, pdt_real_t rel, pdt_real_t *x);

#endif /* PDT_LINALG_H */
