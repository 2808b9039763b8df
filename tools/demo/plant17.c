#include "plant17.h"

#include <math.h>

/* (17) as a cascade of first-order sections, each zero paired with a lag so
 * that every section is proper: (T s + 1)/(tau s + 1) has the state
 * z' = (x - z)/tau and output (T/tau) x + (1 - T/tau) z. */
#define NSEC 7
static const double sec_tau[NSEC] = {2.0, 1.0, 0.4, 0.2, 0.05, 0.05, 0.05};
static const double sec_zero[NSEC] = {0.0, 0.0, -0.3, 0.08, 0.0, 0.0, 0.0};

static void derivs(const double *z, double u, double *dz)
{
    double x = u;
    for (int i = 0; i < NSEC; i++) {
        dz[i] = (x - z[i]) / sec_tau[i];
        double r = sec_zero[i] / sec_tau[i];
        x = r * x + (1.0 - r) * z[i];
    }
}

static double output(const double *z, double u)
{
    double x = u;
    for (int i = 0; i < NSEC; i++) {
        double r = sec_zero[i] / sec_tau[i];
        x = r * x + (1.0 - r) * z[i];
    }
    return x;
}

static void rk4(double *z, double u, double h)
{
    double k1[NSEC], k2[NSEC], k3[NSEC], k4[NSEC], t[NSEC];
    derivs(z, u, k1);
    for (int i = 0; i < NSEC; i++) t[i] = z[i] + 0.5 * h * k1[i];
    derivs(t, u, k2);
    for (int i = 0; i < NSEC; i++) t[i] = z[i] + 0.5 * h * k2[i];
    derivs(t, u, k3);
    for (int i = 0; i < NSEC; i++) t[i] = z[i] + h * k3[i];
    derivs(t, u, k4);
    for (int i = 0; i < NSEC; i++) z[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
}

void plant17_simulate(const double *u, size_t n, double Ts, unsigned substeps, double *y)
{
    double z[NSEC] = {0};
    double h = Ts / (double)substeps;
    double uk = 0.0;
    for (size_t k = 0; k < n; k++) {
        /* The sample at k sees the input held since k - 1 (the hold). */
        y[k] = output(z, uk);
        uk = u[k];
        for (unsigned s = 0; s < substeps; s++) rk4(z, uk, h);
    }
}

double plant17_step(double t, double dt)
{
    double z[NSEC] = {0};
    if (t <= 0.0) return 0.0;
    size_t steps = (size_t)ceil(t / dt);
    double h = t / (double)steps;
    for (size_t s = 0; s < steps; s++) rk4(z, 1.0, h);
    return output(z, 1.0);
}

void plant17_step_grid(double dt_out, size_t count, unsigned substeps, double *out)
{
    double z[NSEC] = {0};
    double h = dt_out / (double)substeps;
    for (size_t i = 0; i < count; i++) {
        out[i] = output(z, i == 0 ? 0.0 : 1.0);
        for (unsigned s = 0; s < substeps; s++) rk4(z, 1.0, h);
    }
}

void plant17_freq(double w, double *mag, double *phase)
{
    double m = 1.0, p = 0.0;
    for (int i = 0; i < NSEC; i++) {
        m *= sqrt(1.0 + (sec_zero[i] * w) * (sec_zero[i] * w)) /
             sqrt(1.0 + (sec_tau[i] * w) * (sec_tau[i] * w));
        p += atan(sec_zero[i] * w) - atan(sec_tau[i] * w);
    }
    *mag = m;
    *phase = p;
}
