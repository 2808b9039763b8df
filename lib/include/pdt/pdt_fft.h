/*
 * pdtfit real FFT: radix-2, in place, power-of-two sizes from 16 to
 * 2^PDT_FFT_MAX_LOG2, twiddles computed once at init into caller memory.
 *
 * Packed spectrum layout (as CMSIS-DSP's arm_rfft_fast_f32), n reals:
 *   buf[0] = Re X[0], buf[1] = Re X[n/2],
 *   buf[2k] = Re X[k], buf[2k+1] = Im X[k]  for k = 1 .. n/2 - 1,
 * where X[k] = sum_{j=0}^{n-1} x[j] e^{-2 pi i j k / n} (numpy.fft.rfft's
 * convention, unnormalised). The inverse scales by 1/n so that
 * inverse(forward(x)) = x.
 */
#ifndef PDT_FFT_H
#define PDT_FFT_H

#include "pdt/pdt_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Bytes of workspace a size-n transform needs: its twiddle table, n/2
 * reals (cos and sin of 2 pi k / n for k = 0 .. n/4 - 1). A constant
 * expression for static arrays; it does not check n (the function below
 * does). */
#define PDT_FFT_WORKSPACE_SIZE(n) (((size_t)(n) / 2u) * sizeof(pdt_real_t))

/* The transform instance. Fill it with pdt_fft_init; its fields are private
 * and constant after init, so one instance may serve several callers (the
 * transforms only read it and the twiddle table). A zero-filled instance is
 * "uninitialised" and refused by every call. */
typedef struct pdt_fft {
    size_t n;               /* transform size, 0 before init */
    const pdt_real_t *twid; /* n/4 pairs (cos, sin) of 2 pi k / n, caller memory */
} pdt_fft_t;

/* Workspace bytes for a size-n transform, or 0 if n is not a power of two
 * in [16, 2^PDT_FFT_MAX_LOG2]. */
size_t pdt_fft_workspace_size(size_t n);

/* Prepares f for size-n transforms and writes the twiddle table into work.
 * work: at least pdt_fft_workspace_size(n) bytes, aligned for pdt_real_t,
 * owned by the caller, which must keep it alive and unchanged while f is in
 * use; f keeps a pointer to it. O(n) sin/cos evaluations.
 * Returns:
 *  PDT_ERR_ARG    f NULL, or work not aligned for pdt_real_t;
 *  PDT_ERR_LENGTH n not a power of two in [16, 2^PDT_FFT_MAX_LOG2];
 *  PDT_ERR_NOMEM  work NULL, or work_len below pdt_fft_workspace_size(n).
 * On error neither f nor work is written. */
pdt_status_t pdt_fft_init(pdt_fft_t *f, size_t n, void *work, size_t work_len);

/* Forward transform, in place: buf holds n real samples on entry and the
 * packed spectrum above on return (unnormalised, same units as the samples
 * times the sample count). O(n log n), no other memory.
 * Returns PDT_ERR_ARG for a NULL f or buf or an uninitialised f; buf is then
 * untouched. */
pdt_status_t pdt_fft_forward(const pdt_fft_t *f, pdt_real_t *buf);

/* Inverse of pdt_fft_forward, in place: buf holds a packed spectrum on entry
 * and n real samples on return, scaled by 1/n so that the round trip gives
 * the samples back. Same cost and errors as pdt_fft_forward. */
pdt_status_t pdt_fft_inverse(const pdt_fft_t *f, pdt_real_t *buf);

/* Magnitudes |X[k]| for k = 0 .. n/2 (n/2 + 1 values into mag) of the packed
 * spectrum spec (n values). mag may be spec itself (in
 * place: spec is then overwritten) but must not overlap it otherwise.
 * Returns PDT_ERR_ARG for a NULL f, spec or mag, or an uninitialised f; mag
 * is then untouched. */
pdt_status_t pdt_fft_magnitude(const pdt_fft_t *f, const pdt_real_t *spec, pdt_real_t *mag);

#ifdef __cplusplus
}
#endif

#endif /* PDT_FFT_H */
