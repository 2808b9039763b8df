#include "plant17.h"

#include <math.h>

#include "sim_plant.h"

/* (17) as the shared simulator takes it: seven lags, two zeros. */
static const double lags17[7] = {2.0, 1.0, 0.4, 0.2, 0.05, 0.05, 0.05};
static const double zeros17[2] = {-0.3, 0.08};

static int plant17_init(sim_plant_t *p, double Ts, double *hist)
{
    sim_plant_desc_t d = {1.0, lags17, 7u, zeros17, 2u, 0.0, 0.0, false, 0.0};
    return sim_plant_init(p, &d, Ts, 0.0, 0.0, hist, 2u);
}

void plant17_simulate(const double *u, size_t n, double Ts, double *y)
{
    sim_plant_t p;
    double hist[2];
    if (plant17_init(&p, Ts, hist) == 0) {
        sim_plant_run(&p, u, n, y);
    }
}

void plant17_step_grid(double dt_out, size_t count, double *out)
{
    sim_plant_t p;
    double hist[2];
    if (plant17_init(&p, dt_out, hist) != 0) {
        return;
    }
    for (size_t i = 0; i < count; i++) {
        out[i] = sim_plant_output(&p);
        sim_plant_apply(&p, 1.0);
    }
}

void plant17_freq(double w, double *mag, double *phase)
{
    sim_plant_desc_t d = {1.0, lags17, 7u, zeros17, 2u, 0.0, 0.0, false, 0.0};
    sim_plant_freq(&d, w, mag, phase);
}
