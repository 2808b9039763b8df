/* autotune-sim's closed loop: the gains the autotune handed out, run by
 * pdt_pid on the same simulated plant, and their robustness on it. */
#ifndef PDTFIT_LOOP_SIM_H
#define PDTFIT_LOOP_SIM_H

#include "pdt/pdt.h"
#include "sim_plant.h"

typedef struct loop_figs {
    double Ms;        /* max |1 / (1 + C G)| on the true plant */
    double iae_sp;    /* IAE of the set-point step, per unit step, s */
    double overshoot; /* of the set-point step, percent */
    double iae_load;  /* IAE of the load step at the plant's input, per
                          * unit of the step, output units s */
    int stable;       /* the loop settled (both errors decayed) */
} loop_figs_t;

/* The loop on plant d (started at rest at u0, y0) at scan period Ts with
 * the ideal gains g: a set-point step of `step` output units, after
 * `horizon` s a load step at the plant's input of step / |K|, for another
 * `horizon` s; noise-free. The controller is pdt_pid (derivative on the
 * measurement, filter Tf of g), its output limits u_lo .. u_hi. */
void loop_sim_run(const sim_plant_desc_t *d, double Ts, const pdt_tune_gains_t *g, double u0,
                  double y0, double u_lo, double u_hi, double step, double horizon,
                  loop_figs_t *out);

#endif
