/*
 * pdtfit: the version, the real type and the status codes (pdt_status.h)
 * shared by every module.
 */
#ifndef PDT_COMMON_H
#define PDT_COMMON_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "pdt/pdt_config.h"
#include "pdt/pdt_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The one version number of pdtfit; CMake reads it from here. */
/* CMake and the package checks read these lines as written. */
/* clang-format off */
#define PDT_VERSION_MAJOR 0
#define PDT_VERSION_MINOR 3
#define PDT_VERSION_PATCH 0
#define PDT_VERSION_STRING "0.3.0"
/* clang-format on */

#if PDT_REAL_DOUBLE
typedef double pdt_real_t;
#else
typedef float pdt_real_t;
#endif

/* Delay bounds that follow the record length: a delay_max of
 * PDT_DELAY_HALF means n / 2 samples, PDT_DELAY_QUARTER n / 4 (rounded
 * down), in every module that takes a delay_max. */
#define PDT_DELAY_HALF    ((size_t)-1)
#define PDT_DELAY_QUARTER ((size_t)-2)

/* State of the library's random generator (PCG32, lib/src/pdt_ga.h), for
 * contexts that carry one; private. */
typedef struct pdt_rng {
    uint64_t state;
    uint64_t inc; /* odd */
} pdt_rng_t;

#ifdef __cplusplus
}
#endif

#endif /* PDT_COMMON_H */
