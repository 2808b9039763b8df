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

/* The faults autotune-sim adds to the plant (docs/autotune.md, "Faults"),
 * each off at 0. In the order a scan meets them:
 *   actuator: the command c passes a backlash of width `stiction` (the
 *     valve stays where it is until c has moved more than `stiction` away
 *     from it, then follows c at that distance), then a rate limit: the
 *     position moves by at most u_rate Ts per scan (u_rate in input units
 *     per s), and is held over the scan;
 *   load: `load` input units added to the position at the plant's input
 *     from the first scan at or after load_t s;
 *   sensor: the process value is the plant's output plus drift t (drift in
 *     pv units per s, t the scan's time) plus the noise, read in steps of
 *     `quant` (rounded to the nearest multiple). */
typedef struct fault_cfg {
    int has_load;
    double load_t, load;
    double drift, quant, u_rate, stiction;
} fault_cfg_t;

/* The actuator's state: the backlash's output and the valve position. */
typedef struct fault_state {
    double backlash;
    double pos;
} fault_state_t;

/* Whether any fault is set. */
int fault_any(const fault_cfg_t *f);

/* At rest at the command u0. */
void fault_init(fault_state_t *s, double u0);

/* The valve position held over this scan for the command c, Ts s. */
double fault_actuator(const fault_cfg_t *f, fault_state_t *s, double c, double Ts);

/* The load at the plant's input at time t s. */
double fault_load(const fault_cfg_t *f, double t);

/* The process value read at time t s for the plant output y (noise
 * included). */
double fault_sensor(const fault_cfg_t *f, double y, double t);

#endif
