/*
 * Real FFT of power-of-two size n.
 *
 * The n real samples are read as m = n/2 complex numbers z[j] = x[2j] +
 * i x[2j+1] (which is exactly how they already lie in memory), transformed
 * by an iterative radix-2 decimation-in-time complex FFT, and then split:
 * with Z = FFT(z), the spectra of the even and odd samples are
 *   E[k] = (Z[k] + conj Z[m-k]) / 2,   O[k] = (Z[k] - conj Z[m-k]) / (2i),
 * and X[k] = E[k] + W^k O[k], X[m-k] = conj(E[k] - W^k O[k]), W = e^{-2 pi i/n}.
 * The inverse solves the same relations for Z and runs the forward complex
 * FFT on conj(Z), since ifft(Z) = conj(fft(conj Z)) / m.
 *
 * One table serves both steps: W^t for t = 0 .. n/4 - 1, stored as
 * (cos, sin) pairs of 2 pi t / n. The complex FFT needs W^(2t) up to a half
 * turn; the second quarter comes from the first by W^(t + n/4) = -i W^t.
 */
#include "pdt/pdt_fft.h"

#include "pdt_internal.h"

/* pi - 3. The twiddle angle is formed as (3 k + (pi - 3) k) * 2/n: 3 k is
 * exact in the real type for every supported size and 2/n is a power of
 * two, so the only rounding falls on the small second term and on the sum,
 * and the angle is good to about half an ulp (2 pi k / n in one product
 * would carry the error of the rounded pi times k). */
#define FFT_PI_MINUS_3 PDT_R(0.14159265358979323846264338327950288)

static bool fft_size_ok(size_t n)
{
    return n >= 16u && n <= ((size_t)1u << PDT_FFT_MAX_LOG2) && (n & (n - 1u)) == 0u;
}

static bool fft_ready(const pdt_fft_t *f)
{
    return f != NULL && f->twid != NULL && fft_size_ok(f->n);
}

static void fft_twiddles(pdt_real_t *tw, size_t n)
{
    const size_t quarter = n / 4u;
    const size_t eighth = n / 8u;
    const pdt_real_t scale = PDT_R(2.0) / (pdt_real_t)n;

    for (size_t t = 0; t < quarter; t++) {
        /* Past an eighth of a turn, evaluate at the complementary angle so
         * that sin and cos always see arguments in [0, pi/4]. */
        const size_t k = (t <= eighth) ? t : quarter - t;
        const pdt_real_t kr = (pdt_real_t)k;
        const pdt_real_t a = (PDT_R(3.0) * kr + FFT_PI_MINUS_3 * kr) * scale;
        const pdt_real_t c = pdt_cos(a);
        const pdt_real_t s = pdt_sin(a);
        tw[2u * t] = (t <= eighth) ? c : s;
        tw[2u * t + 1u] = (t <= eighth) ? s : c;
    }
}

/* Bit-reversal permutation of m complex values (interleaved re, im). The
 * reversed counter j is advanced by adding one from the top bit down. */
static void fft_bitrev(pdt_real_t *z, size_t m)
{
    size_t j = 0;
    for (size_t i = 0; i + 1u < m; i++) {
        if (i < j) {
            const pdt_real_t re = z[2u * i];
            const pdt_real_t im = z[2u * i + 1u];
            z[2u * i] = z[2u * j];
            z[2u * i + 1u] = z[2u * j + 1u];
            z[2u * j] = re;
            z[2u * j + 1u] = im;
        }
        size_t bit = m >> 1;
        while ((j & bit) != 0u) {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
    }
}

/* z[a], z[b] = z[a] + w z[b], z[a] - w z[b] with w = wr + i wi. */
static inline void fft_butterfly(pdt_real_t *z, size_t a, size_t b, pdt_real_t wr, pdt_real_t wi)
{
    const pdt_real_t br = z[2u * b];
    const pdt_real_t bi = z[2u * b + 1u];
    const pdt_real_t tr = wr * br - wi * bi;
    const pdt_real_t ti = wr * bi + wi * br;
    const pdt_real_t ar = z[2u * a];
    const pdt_real_t ai = z[2u * a + 1u];
    z[2u * a] = ar + tr;
    z[2u * a + 1u] = ai + ti;
    z[2u * b] = ar - tr;
    z[2u * b + 1u] = ai - ti;
}

/* Forward complex FFT of m = n/2 points in place, tw the size-n table. */
static void fft_complex(pdt_real_t *z, size_t m, const pdt_real_t *tw)
{
    fft_bitrev(z, m);

    /* Length-2 butterflies have the twiddle 1: no multiplications. */
    for (size_t i = 0; i < 2u * m; i += 4u) {
        const pdt_real_t ar = z[i];
        const pdt_real_t ai = z[i + 1u];
        const pdt_real_t br = z[i + 2u];
        const pdt_real_t bi = z[i + 3u];
        z[i] = ar + br;
        z[i + 1u] = ai + bi;
        z[i + 2u] = ar - br;
        z[i + 3u] = ai - bi;
    }

    /* Butterflies of half-length h need W_{2h}^k = W^(k m / h), k < h. For
     * k < h/2 that is a table entry; for k + h/2 it is -i times the same
     * entry, so both are done with one table read. */
    for (size_t h = 2u; h < m; h <<= 1) {
        const size_t step = m / h;
        const size_t half = h / 2u;
        for (size_t k = 0; k < half; k++) {
            const pdt_real_t c = tw[2u * k * step];
            const pdt_real_t s = tw[2u * k * step + 1u];
            for (size_t g = k; g < m; g += 2u * h) {
                fft_butterfly(z, g, g + h, c, -s);
                fft_butterfly(z, g + half, g + half + h, -s, -c);
            }
        }
    }
}

size_t pdt_fft_workspace_size(size_t n)
{
    return fft_size_ok(n) ? PDT_FFT_WORKSPACE_SIZE(n) : 0u;
}

pdt_status_t pdt_fft_init(pdt_fft_t *f, size_t n, void *work, size_t work_len)
{
    if (f == NULL) {
        return PDT_ERR_ARG;
    }
    if (!fft_size_ok(n)) {
        return PDT_ERR_LENGTH;
    }
    if (work == NULL) {
        return PDT_ERR_NOMEM;
    }
    if (!pdt_aligned(work)) {
        return PDT_ERR_ARG;
    }
    if (work_len < PDT_FFT_WORKSPACE_SIZE(n)) {
        return PDT_ERR_NOMEM;
    }

    /* The alignment was checked above. */
    pdt_real_t *tw = (pdt_real_t *)work;
    fft_twiddles(tw, n);
    f->n = n;
    f->twid = tw;
    return PDT_OK;
}

pdt_status_t pdt_fft_forward(const pdt_fft_t *f, pdt_real_t *buf)
{
    if (!fft_ready(f) || buf == NULL) {
        return PDT_ERR_ARG;
    }
    const size_t m = f->n / 2u;
    const size_t quarter = f->n / 4u;
    const pdt_real_t *tw = f->twid;

    fft_complex(buf, m, tw);

    /* Z[0] = E[0] + i O[0] with E[0], O[0] real: X[0] = E + O, X[n/2] = E - O. */
    const pdt_real_t z0r = buf[0];
    const pdt_real_t z0i = buf[1];
    buf[0] = z0r + z0i;
    buf[1] = z0r - z0i;
    /* At k = n/4, W^k = -i and the split reduces to X = conj Z. */
    buf[2u * quarter + 1u] = -buf[2u * quarter + 1u];

    for (size_t k = 1u; k < quarter; k++) {
        const size_t j = m - k;
        const pdt_real_t zr = buf[2u * k];
        const pdt_real_t zi = buf[2u * k + 1u];
        const pdt_real_t yr = buf[2u * j];
        const pdt_real_t yi = buf[2u * j + 1u];
        const pdt_real_t er = PDT_R(0.5) * (zr + yr);
        const pdt_real_t ei = PDT_R(0.5) * (zi - yi);
        const pdt_real_t odr = PDT_R(0.5) * (zi + yi);
        const pdt_real_t odi = PDT_R(0.5) * (yr - zr);
        const pdt_real_t c = tw[2u * k];
        const pdt_real_t s = tw[2u * k + 1u];
        /* t = (c - i s) O */
        const pdt_real_t tr = c * odr + s * odi;
        const pdt_real_t ti = c * odi - s * odr;
        buf[2u * k] = er + tr;
        buf[2u * k + 1u] = ei + ti;
        buf[2u * j] = er - tr;
        buf[2u * j + 1u] = ti - ei;
    }
    return PDT_OK;
}

pdt_status_t pdt_fft_inverse(const pdt_fft_t *f, pdt_real_t *buf)
{
    if (!fft_ready(f) || buf == NULL) {
        return PDT_ERR_ARG;
    }
    const size_t n = f->n;
    const size_t m = n / 2u;
    const size_t quarter = n / 4u;
    const pdt_real_t *tw = f->twid;

    /* Rebuild conj(2 Z) in place; the factor 2 and the 1/m of the inverse
     * complex FFT are applied together as 1/n at the end (exact, a power of
     * two). */
    const pdt_real_t x0 = buf[0];
    const pdt_real_t xh = buf[1];
    buf[0] = x0 + xh;
    buf[1] = xh - x0;
    buf[2u * quarter] = PDT_R(2.0) * buf[2u * quarter];
    buf[2u * quarter + 1u] = PDT_R(2.0) * buf[2u * quarter + 1u];

    for (size_t k = 1u; k < quarter; k++) {
        const size_t j = m - k;
        const pdt_real_t xr = buf[2u * k];
        const pdt_real_t xi = buf[2u * k + 1u];
        const pdt_real_t yr = buf[2u * j];
        const pdt_real_t yi = buf[2u * j + 1u];
        /* 2E = X[k] + conj X[m-k]; D = X[k] - conj X[m-k] = 2 W^k O. */
        const pdt_real_t er = xr + yr;
        const pdt_real_t ei = xi - yi;
        const pdt_real_t dr = xr - yr;
        const pdt_real_t di = xi + yi;
        const pdt_real_t c = tw[2u * k];
        const pdt_real_t s = tw[2u * k + 1u];
        /* 2O = (c + i s) D */
        const pdt_real_t odr = c * dr - s * di;
        const pdt_real_t odi = c * di + s * dr;
        /* 2Z[k] = 2E + i 2O, 2Z[m-k] = conj(2E) + i conj(2O); stored conjugated. */
        buf[2u * k] = er - odi;
        buf[2u * k + 1u] = -(ei + odr);
        buf[2u * j] = er + odi;
        buf[2u * j + 1u] = ei - odr;
    }

    fft_complex(buf, m, tw);

    const pdt_real_t scale = PDT_R(1.0) / (pdt_real_t)n;
    for (size_t i = 0; i < m; i++) {
        buf[2u * i] = scale * buf[2u * i];
        buf[2u * i + 1u] = -scale * buf[2u * i + 1u];
    }
    return PDT_OK;
}

pdt_status_t pdt_fft_magnitude(const pdt_fft_t *f, const pdt_real_t *spec, pdt_real_t *mag)
{
    if (!fft_ready(f) || spec == NULL || mag == NULL) {
        return PDT_ERR_ARG;
    }
    const size_t half = f->n / 2u;

    /* Ascending k reads spec[2k], spec[2k + 1] before mag[k] is written, so
     * mag == spec works once spec[1] (Re X[n/2]) is saved. */
    const pdt_real_t nyquist = pdt_fabs(spec[1]);
    mag[0] = pdt_fabs(spec[0]);
    for (size_t k = 1u; k < half; k++) {
        const pdt_real_t re = spec[2u * k];
        const pdt_real_t im = spec[2u * k + 1u];
        mag[k] = pdt_sqrt(re * re + im * im);
    }
    mag[half] = nyquist;
    return PDT_OK;
}
