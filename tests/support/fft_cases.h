/*
 * The FFT reference vectors (tests/vectors/fft_vectors.h, generated) as one
 * table of cases, for the host and the target tests.
 */
#ifndef PDT_FFT_CASES_H
#define PDT_FFT_CASES_H

#include <stddef.h>
#include <stdint.h>

#include "fft_vectors.h"

typedef struct fft_case {
    size_t n;
    const int16_t *q;   /* the input, quantised */
    const double *spec; /* its spectrum */
    const double *mag;  /* and magnitude */
} fft_case_t;

static const fft_case_t fft_cases[] = {
    {16u, fft_q_16, fft_spec_16, fft_mag_16},
    {32u, fft_q_32, fft_spec_32, fft_mag_32},
    {64u, fft_q_64, fft_spec_64, fft_mag_64},
    {128u, fft_q_128, fft_spec_128, fft_mag_128},
    {256u, fft_q_256, fft_spec_256, fft_mag_256},
    {1024u, fft_q_1024, fft_spec_1024, fft_mag_1024},
    {8192u, fft_q_8192, fft_spec_8192, fft_mag_8192},
};
#define FFT_NCASES (sizeof fft_cases / sizeof fft_cases[0])

#endif /* PDT_FFT_CASES_H */
