/* autotune-sim's closed loop on the true plant. */
#include "loop_sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI_VALUE 3.14159265358979323846

/* |1 / (1 + C G)| at w of the ideal PID (filtered derivative) on the
 * described plant, with the half scan of dead time the zero-order hold of
 * the controller's output adds. */
static double sensitivity(const sim_plant_desc_t *d, const pdt_tune_gains_t *g, double Ts, double w)
{
    double mag, ph;
    sim_plant_freq(d, w, &mag, &ph);
    ph -= w * Ts / 2.0;
    const double Kc = (double)g->Kc, Ti = (double)g->tauI, Td = (double)g->tauD;
    const double Tf = (double)g->Tf;
    /* C = Kc (1 + 1 / (j w Ti) + j w Td / (1 + j w Tf)) */
    double cr = 1.0, ci = Ti > 0.0 ? -1.0 / (w * Ti) : 0.0;
    const double den = 1.0 + (w * Tf) * (w * Tf);
    cr += w * Td * (w * Tf) / den;
    ci += w * Td / den;
    cr *= Kc;
    ci *= Kc;
    const double gr = mag * cos(ph), gi = mag * sin(ph);
    const double lr = 1.0 + cr * gr - ci * gi, li = cr * gi + ci * gr;
    return 1.0 / hypot(lr, li);
}

static double max_sensitivity(const sim_plant_desc_t *d, const pdt_tune_gains_t *g, double Ts,
                              double t_scale)
{
    double ms = 0.0;
    const double w_nyq = PI_VALUE / Ts;
    for (int k = 0; k <= 1200; k++) {
        const double w = 1e-3 / t_scale * pow(10.0, (double)k / 200.0);
        if (w > w_nyq) break;
        const double s = sensitivity(d, g, Ts, w);
        ms = s > ms ? s : ms;
    }
    return ms;
}

/* One segment of the run: `scans` scans at set-point sp with the input
 * disturbance dist; returns the IAE and tracks the largest output. */
static double run_segment(sim_plant_t *p, pdt_pid_t *pid, double sp, double dist, long scans,
                          double Ts, double *ymax, double *last_err)
{
    double iae = 0.0, e = 0.0;
    for (long k = 0; k < scans; k++) {
        const double y = sim_plant_output(p);
        pdt_real_t u = 0;
        if (pdt_pid_update(pid, (pdt_real_t)sp, (pdt_real_t)y, &u) != PDT_OK) u = pid->u;
        e = sp - y;
        iae += fabs(e) * Ts;
        *ymax = y > *ymax ? y : *ymax;
        sim_plant_apply(p, (double)u + dist);
    }
    *last_err = fabs(e);
    return iae;
}

void loop_sim_run(const sim_plant_desc_t *d, double Ts, const pdt_tune_gains_t *g, double u0,
                  double y0, double u_lo, double u_hi, double step, double horizon,
                  loop_figs_t *out)
{
    memset(out, 0, sizeof *out);
    double t_scale = d->delay;
    for (size_t i = 0; i < d->n_lags; i++) t_scale += d->lags[i];
    if (d->wn > 0.0) t_scale += 1.0 / d->wn;
    out->Ms = max_sensitivity(d, g, Ts, t_scale > 0.0 ? t_scale : Ts);
    const size_t hist_len = SIM_PLANT_HIST_LEN(d->delay, Ts);
    double *hist = malloc(hist_len * sizeof *hist);
    sim_plant_t p;
    pdt_pid_config_t pc;
    pdt_pid_t pid;
    pdt_pid_config_default(&pc);
    pc.Ts = (pdt_real_t)Ts;
    pc.u_min = (pdt_real_t)u_lo;
    pc.u_max = (pdt_real_t)u_hi;
    if (!hist || sim_plant_init(&p, d, Ts, u0, y0, hist, hist_len) != 0 ||
        pdt_pid_init_from_gains(&pid, &pc, g, PDT_PID_IDEAL, (pdt_real_t)u0) != PDT_OK) {
        free(hist);
        out->iae_sp = out->iae_load = (double)NAN;
        out->overshoot = (double)NAN;
        return;
    }
    const long scans = (long)(horizon / Ts) + 1;
    const double K = fabs(d->K) > 0.0 ? fabs(d->K) : 1.0;
    double ymax = y0, e_sp, e_ld;
    const double sign = step >= 0.0 ? 1.0 : -1.0;
    out->iae_sp = run_segment(&p, &pid, y0 + step, 0.0, scans, Ts, &ymax, &e_sp) / fabs(step);
    out->overshoot = 100.0 * (sign * (ymax - (y0 + step))) / fabs(step);
    if (out->overshoot < 0.0) out->overshoot = 0.0;
    out->iae_load =
        run_segment(&p, &pid, y0 + step, step / K, scans, Ts, &ymax, &e_ld) / fabs(step / K);
    out->stable = e_sp < 0.02 * fabs(step) && e_ld < 0.02 * fabs(step) && isfinite(out->iae_load);
    free(hist);
}

int fault_any(const fault_cfg_t *f)
{
    return f->has_load || f->drift != 0.0 || f->quant > 0.0 || f->u_rate > 0.0 || f->stiction > 0.0;
}

void fault_init(fault_state_t *s, double u0)
{
    s->backlash = u0;
    s->pos = u0;
}

double fault_actuator(const fault_cfg_t *f, fault_state_t *s, double c, double Ts)
{
    if (f->stiction > 0.0) {
        if (c > s->backlash + f->stiction) s->backlash = c - f->stiction;
        if (c < s->backlash - f->stiction) s->backlash = c + f->stiction;
    } else {
        s->backlash = c;
    }
    const double step = f->u_rate > 0.0 ? f->u_rate * Ts : HUGE_VAL;
    double d = s->backlash - s->pos;
    if (d > step) d = step;
    if (d < -step) d = -step;
    s->pos += d;
    return s->pos;
}

double fault_load(const fault_cfg_t *f, double t)
{
    /* A scan's time is a multiple of Ts computed in double: a load at a
     * scan's nominal time enters at that scan. */
    return f->has_load && t >= f->load_t - 1e-9 * (1.0 + fabs(f->load_t)) ? f->load : 0.0;
}

double fault_sensor(const fault_cfg_t *f, double y, double t)
{
    double pv = y + f->drift * t;
    if (f->quant > 0.0) pv = f->quant * floor(pv / f->quant + 0.5);
    return pv;
}
