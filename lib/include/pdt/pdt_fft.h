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

/* Bytes of workspace a size-n transform needs (its twiddle table):
 * 3n/4 reals. Usable for static arrays. */
#define PDT_RFFT_WORKSPACE_SIZE(n) ((size_t)(3u * (size_t)(n) / 4u) * sizeof(pdt_real_t))

/* The transform instance. Fill it with pdt_rfft_init; its fields are private
 * and constant after init, so one instance may serve several callers. */
typedef struct pdt_rfft {
    size_t n;                /* transform size */
    unsigned log2n;          /* log2(n) */
    const pdt_real_t *twid;  /* n/2 reals: cos, sin of the n/2-point complex FFT (n/4 pairs) */
    const pdt_real_t *split; /* n/4 pairs: cos, sin for the real split, caller memory */
} pdt_rfft_t;

/* Workspace bytes for size n, or 0 if n is not a supported size. */
size_t pdt_rfft_workspace_size(size_t n);

/* Prepares a size-n transform in work (at least pdt_rfft_workspace_size(n)
 * bytes, aligned for pdt_real_t, owned by the caller and left untouched
 * while the instance is in use).
 * Returns PDT_ERR_ARG (NULL f, misaligned work), PDT_ERR_LENGTH (n not a
 * power of two in range), PDT_ERR_NOMEM (work NULL or too small). */
pdt_status_t pdt_rfft_init(pdt_rfft_t *f, size_t n, void *work, size_t work_len);

/* Forward transform of n reals in buf, in place, into the packed layout
 * above. O(n log n). Returns PDT_ERR_ARG for NULL or an uninitialised f. */
pdt_status_t pdt_rfft_forward(const pdt_rfft_t *f, pdt_real_t *buf);

/* Inverse of pdt_rfft_forward, in place, scaled by 1/n. Same errors. */
pdt_status_t pdt_rfft_inverse(const pdt_rfft_t *f, pdt_real_t *buf);

/* Magnitudes |X[k]| for k = 0 .. n/2 (n/2 + 1 values) from a packed
 * spectrum. mag must not overlap spec. Returns PDT_ERR_ARG for NULL. */
pdt_status_t pdt_rfft_magnitude(const pdt_rfft_t *f, const pdt_real_t *spec, pdt_real_t *mag);

#ifdef __cplusplus
}
#endif

#endif /* PDT_FFT_H */
