/*
 * The parametric bootstrap of an identification, for the command line and
 * the Python binding (host code: it allocates). Where the Fisher
 * information is a poor guide to a parameter's spread (a SOPDT's dead time
 * against its second lag from a step: a curved valley), the spread of the
 * answers on records simulated from the model gives intervals that hold
 * (docs/uncertainty.md).
 */
#ifndef PDTCLI_UNCERT_H
#define PDTCLI_UNCERT_H

#include <stddef.h>

#include "pdt/pdt.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Runs of the bootstrap by default. */
#define PDTCLI_BOOT_RUNS 50u

typedef struct pdtcli_boot {
    unsigned runs, ok; /* records simulated; identified */
    uint32_t have;     /* bit i: printed parameter i (pdt_ident_par_t) */
    double std[PDT_IDENT_PAR_COUNT];
    double lo[PDT_IDENT_PAR_COUNT], hi[PDT_IDENT_PAR_COUNT]; /* 2.5 %, 97.5 % */
    double cov[PDT_IDENT_PAR_COUNT][PDT_IDENT_PAR_COUNT];
} pdtcli_boot_t;

/* The printed parameters' values of m with offset y0 into v (NaN where the
 * form has none); returns the pdt_ident_par_t bits that exist. */
uint32_t pdtcli_printed_values(const pdt_model_t *m, double y0, double v[PDT_IDENT_PAR_COUNT]);

/* The bootstrap of r, the answer of pdt_identify with cfg on the record
 * u, y of n samples: runs records of the model's output on u plus noise of
 * the residual's variance and lag-one correlation (an AR(1) process), each
 * identified with cfg and its own seed (from cfg->seed); the spread of
 * the printed parameters into *out. Deterministic. Returns 0, or -1 when
 * memory runs out or fewer than 2 runs give a model. */
int pdtcli_bootstrap(const pdt_ident_config_t *cfg, const pdt_ident_result_t *r,
                     const pdt_real_t *u, const pdt_real_t *y, size_t n, unsigned runs,
                     pdtcli_boot_t *out);

#ifdef __cplusplus
}
#endif

#endif /* PDTCLI_UNCERT_H */
