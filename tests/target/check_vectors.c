/*
 * The core's vector checks on the target: the generated reference vectors
 * of tests/vectors/ (numpy, double precision) against the library as built
 * for the Cortex-M4F, with the host tests' tolerances. A representative
 * subset of the host tests: every FFT size, every discretisation case and
 * simulation, every model's step and frequency response, every cost record
 * under every time cost, frequency weighting and the combined cost.
 */
#include <math.h>
#include <string.h>

#include "target_checks.h"
#include "target_util.h"

#include "cost_vectors.h"
#include "discrete_vectors.h"
#include "fft_cases.h"
#include "model_vectors.h"

#if PDT_REAL_DOUBLE
#define FFT_MIN_SNR_DB 250.0
#define FFT_PEAK_RTOL  1e-12
#define COEF_RTOL      1e-12
#define SIM_SNR_DB     250.0
#define STEP_RTOL      1e-12
#define FREQ_RTOL      1e-13
#define COST_RTOL      1e-9
#else
#define FFT_MIN_SNR_DB 100.0
#define FFT_PEAK_RTOL  1e-5
#define COEF_RTOL      5e-6
#define SIM_SNR_DB     100.0
#define STEP_RTOL      2e-6
#define FREQ_RTOL      1e-6
#define COST_RTOL      1e-4
#endif

/* ---- FFT --------------------------------------------------------------- */

#define FFT_NMAX 8192u

static pdt_real_t g_fft_work[FFT_NMAX / 2u + CANARY_COUNT];
static pdt_real_t g_fft_buf[FFT_NMAX + CANARY_COUNT];
static pdt_real_t g_fft_mag[FFT_NMAX / 2u + 1u + CANARY_COUNT];
static double g_fft_ref[FFT_NMAX];

/* Both measures of the host test: the SNR and the largest error relative
 * to the reference's peak. */
static bool fft_compare(const pdt_real_t *got, const double *ref, size_t len, double *snr,
                        double *err_peak)
{
    *snr = snr_db(got, ref, len);
    *err_peak = max_abs_err(got, ref, len) / peak_abs(ref, len);
    return *snr >= FFT_MIN_SNR_DB && *err_peak <= FFT_PEAK_RTOL;
}

int target_check_fft(void)
{
    int failed = 0;
    for (size_t c = 0; c < FFT_NCASES; c++) {
        const fft_case_t *tc = &fft_cases[c];
        const size_t n = tc->n;
        const size_t ws = pdt_fft_workspace_size(n);
        pdt_fft_t f;
        bool ok = ws == PDT_FFT_WORKSPACE_SIZE(n);
        double snr_f = 0.0, snr_i = 0.0, snr_m = 0.0, ep_f = 0.0, ep_i = 0.0, ep_m = 0.0;

        canary_fill(g_fft_work + ws / sizeof(pdt_real_t), CANARY_COUNT);
        ok = ok && pdt_fft_init(&f, n, g_fft_work, ws) == PDT_OK;
        ok = ok && canary_intact(g_fft_work + ws / sizeof(pdt_real_t), CANARY_COUNT);
        if (ok) {
            for (size_t j = 0; j < n; j++) {
                g_fft_buf[j] = (pdt_real_t)tc->q[j] / (pdt_real_t)FFT_VEC_DENOM;
                g_fft_ref[j] = (double)tc->q[j] / (double)FFT_VEC_DENOM;
            }
            canary_fill(g_fft_buf + n, CANARY_COUNT);
            ok = pdt_fft_forward(&f, g_fft_buf) == PDT_OK &&
                 canary_intact(g_fft_buf + n, CANARY_COUNT);
            ok = fft_compare(g_fft_buf, tc->spec, n, &snr_f, &ep_f) && ok;

            canary_fill(g_fft_mag + n / 2u + 1u, CANARY_COUNT);
            ok = pdt_fft_magnitude(&f, g_fft_buf, g_fft_mag) == PDT_OK && ok;
            ok = canary_intact(g_fft_mag + n / 2u + 1u, CANARY_COUNT) && ok;
            ok = fft_compare(g_fft_mag, tc->mag, n / 2u + 1u, &snr_m, &ep_m) && ok;

            for (size_t j = 0; j < n; j++) {
                g_fft_buf[j] = (pdt_real_t)tc->spec[j];
            }
            ok = pdt_fft_inverse(&f, g_fft_buf) == PDT_OK &&
                 canary_intact(g_fft_buf + n, CANARY_COUNT) && ok;
            ok = fft_compare(g_fft_buf, g_fft_ref, n, &snr_i, &ep_i) && ok;
        }

        tline_t l;
        tl_init(&l);
        tl_str(&l, "fft n=");
        tl_uint(&l, n);
        tl_str(&l, ": SNR forward ");
        tl_num(&l, snr_f, 4);
        tl_str(&l, " dB, inverse ");
        tl_num(&l, snr_i, 4);
        tl_str(&l, " dB, magnitude ");
        tl_num(&l, snr_m, 4);
        tl_str(&l, " dB (min ");
        tl_num(&l, FFT_MIN_SNR_DB, 3);
        tl_str(&l, "); max error/peak ");
        tl_num(&l, fmax(ep_f, fmax(ep_i, ep_m)), 3);
        tl_str(&l, " (max ");
        tl_num(&l, FFT_PEAK_RTOL, 2);
        tl_str(&l, ")");
        failed += t_verdict(ok, &l);
    }
    return failed;
}

/* ---- Models ------------------------------------------------------------ */

/* Model i of the vectors with the dead time Td. */
static pdt_model_t vec_model(int i, double Td)
{
    pdt_model_t m = vector_model(model_kind[i], &model_par[4 * i]);
    if (m.kind == PDT_MODEL_FOPDT) {
        m.p.fopdt.Td = (pdt_real_t)Td;
    } else {
        m.p.sopdt.Td = (pdt_real_t)Td;
    }
    return m;
}

static pdt_real_t g_t[MODEL_VEC_NT];
static pdt_real_t g_y[MODEL_VEC_NT + CANARY_COUNT];
static pdt_real_t g_w[MODEL_VEC_NW];
static pdt_real_t g_mag[MODEL_VEC_NW + CANARY_COUNT];
static pdt_real_t g_ph[MODEL_VEC_NW + CANARY_COUNT];

int target_check_model(void)
{
    double worst_step = 0.0, worst_mag = 0.0, worst_ph = 0.0;
    bool ok_step = true, ok_freq = true;
    for (int i = 0; i < MODEL_VEC_COUNT; i++) {
        pdt_model_t m = vec_model(i, model_par[4 * i + (model_kind[i] == 1 ? 2 : 3)]);
        for (int j = 0; j < MODEL_VEC_NT; j++) {
            g_t[j] = (pdt_real_t)model_t[MODEL_VEC_NT * i + j];
        }
        canary_fill(g_y + MODEL_VEC_NT, CANARY_COUNT);
        ok_step = pdt_model_step(&m, g_t, MODEL_VEC_NT, g_y) == PDT_OK && ok_step;
        ok_step = canary_intact(g_y + MODEL_VEC_NT, CANARY_COUNT) && ok_step;
        for (int j = 0; j < MODEL_VEC_NT; j++) {
            double want = model_step[MODEL_VEC_NT * i + j];
            if (want == 0.0) {
                ok_step = g_y[j] == (pdt_real_t)0.0 && ok_step;
                continue;
            }
            double e = rel_err((double)g_y[j], want);
            worst_step = fmax(worst_step, e);
            ok_step = e <= STEP_RTOL && ok_step;
        }

        for (int j = 0; j < MODEL_VEC_NW; j++) {
            g_w[j] = (pdt_real_t)model_w[MODEL_VEC_NW * i + j];
        }
        canary_fill(g_mag + MODEL_VEC_NW, CANARY_COUNT);
        canary_fill(g_ph + MODEL_VEC_NW, CANARY_COUNT);
        ok_freq = pdt_model_freq(&m, g_w, MODEL_VEC_NW, g_mag, g_ph) == PDT_OK && ok_freq;
        ok_freq = canary_intact(g_mag + MODEL_VEC_NW, CANARY_COUNT) &&
                  canary_intact(g_ph + MODEL_VEC_NW, CANARY_COUNT) && ok_freq;
        bool integ = m.kind == PDT_MODEL_SOPDT && m.p.sopdt.b == (pdt_real_t)0.0;
        for (int j = 0; j < MODEL_VEC_NW; j++) {
            double wm = model_mag[MODEL_VEC_NW * i + j];
            double wp = model_phase[MODEL_VEC_NW * i + j];
            if (integ && g_w[j] == (pdt_real_t)0.0) {
                ok_freq = isinf(g_mag[j]) && g_mag[j] > (pdt_real_t)0.0 && ok_freq;
            } else {
                double e = rel_err((double)g_mag[j], wm);
                worst_mag = fmax(worst_mag, e);
                ok_freq = e <= FREQ_RTOL && ok_freq;
            }
            /* the host test's phase bound: FREQ_RTOL (1 + |phase|) */
            double e = fabs((double)g_ph[j] - wp) / (1.0 + fabs(wp));
            worst_ph = fmax(worst_ph, e);
            ok_freq = e <= FREQ_RTOL && ok_freq;
        }
    }
    int failed = 0;
    tline_t l;
    tl_init(&l);
    tl_str(&l, "model step, ");
    tl_uint(&l, MODEL_VEC_COUNT);
    tl_str(&l, " models: worst relative error ");
    tl_num(&l, worst_step, 3);
    tl_str(&l, " (max ");
    tl_num(&l, STEP_RTOL, 2);
    tl_str(&l, ")");
    failed += t_verdict(ok_step, &l);
    tl_init(&l);
    tl_str(&l, "model frequency response: worst relative error magnitude ");
    tl_num(&l, worst_mag, 3);
    tl_str(&l, ", phase ");
    tl_num(&l, worst_ph, 3);
    tl_str(&l, " (max ");
    tl_num(&l, FREQ_RTOL, 2);
    tl_str(&l, ")");
    failed += t_verdict(ok_freq, &l);
    return failed;
}

/* ---- Discretisation ---------------------------------------------------- */

static double max_abs(const double *v, int n)
{
    double s = 0.0;
    for (int i = 0; i < n; i++) {
        s = fmax(s, fabs(v[i]));
    }
    return s;
}

/* The ZOH coefficients of every case: b and a relative to the largest of
 * the same polynomial, d element by element, and the integer-delay model. */
static int check_coefficients(void)
{
    double worst_b = 0.0, worst_a = 0.0, worst_d = 0.0, worst_int = 0.0;
    bool ok = true;
    for (int c = 0; c < DISC_VEC_COUNT; c++) {
        pdt_model_t m = vec_model(disc_model[c], disc_par[3 * c + 1]);
        pdt_real_t Ts = (pdt_real_t)disc_par[3 * c];
        pdt_discrete_t d;
        pdt_discrete_t di;
        if (pdt_discrete_init(&m, Ts, &d) != PDT_OK ||
            pdt_discrete_init_int(&m, Ts, (size_t)disc_delay[c], &di) != PDT_OK) {
            ok = false;
            continue;
        }
        int order = m.kind == PDT_MODEL_FOPDT ? 1 : 2;
        ok = ok && d.delay == (size_t)disc_delay[c] && d.order == order;
        double sb = max_abs(&disc_b[3 * c], 3);
        double sa = max_abs(&disc_a[2 * c], 2);
        double si = max_abs(&disc_int_b[3 * c], 3);
        for (int j = 0; j < 3; j++) {
            double eb = fabs((double)d.b[j] - disc_b[3 * c + j]) / sb;
            double ei = fabs((double)di.b[j] - disc_int_b[3 * c + j]) / si;
            worst_b = fmax(worst_b, eb);
            worst_int = fmax(worst_int, ei);
            ok = ok && eb <= COEF_RTOL && ei <= COEF_RTOL;
        }
        for (int j = 0; j < order; j++) {
            double ea = fabs((double)d.a[j] - disc_a[2 * c + j]) / sa;
            double ed = rel_err((double)d.d[j], disc_d[2 * c + j]);
            worst_a = fmax(worst_a, ea);
            worst_d = fmax(worst_d, ed);
            ok = ok && ea <= COEF_RTOL && ed <= COEF_RTOL;
        }
    }
    tline_t l;
    tl_init(&l);
    tl_str(&l, "discretize, ");
    tl_uint(&l, DISC_VEC_COUNT);
    tl_str(&l, " cases: worst error b ");
    tl_num(&l, worst_b, 3);
    tl_str(&l, ", a ");
    tl_num(&l, worst_a, 3);
    tl_str(&l, ", d ");
    tl_num(&l, worst_d, 3);
    tl_str(&l, ", integer-delay b ");
    tl_num(&l, worst_int, 3);
    tl_str(&l, " (max ");
    tl_num(&l, COEF_RTOL, 2);
    tl_str(&l, ")");
    return t_verdict(ok, &l);
}

static pdt_real_t g_su[DISC_SIM_N];
static pdt_real_t g_sym[DISC_SIM_N];
static pdt_real_t g_sy[DISC_SIM_N + CANARY_COUNT];
static pdt_real_t g_syh[DISC_SIM_N + CANARY_COUNT];

/* Simulation and prediction of the reference's own (float-rounded)
 * coefficients, as the host test loads them. */
static int check_simulation(void)
{
    int failed = 0;
    for (int s = 0; s < DISC_SIM_CASES; s++) {
        int c = disc_sim_case[s];
        pdt_discrete_t d;
        memset(&d, 0, sizeof d);
        d.delay = (size_t)disc_delay[c];
        d.order = model_kind[disc_model[c]] == 1 ? 1u : 2u;
        for (int j = 0; j < 2; j++) {
            d.a[j] = (pdt_real_t)(float)disc_a[2 * c + j];
        }
        for (int j = 0; j < 3; j++) {
            d.b[j] = (pdt_real_t)(float)disc_b[3 * c + j];
        }
        double a0 = (double)(float)disc_a[2 * c];
        double a1 = (double)(float)disc_a[2 * c + 1];
        if (d.order == 1) {
            d.d[0] = (pdt_real_t)(1.0 + a0);
        } else {
            d.d[0] = (pdt_real_t)(2.0 + a0);
            d.d[1] = (pdt_real_t)(1.0 + a0 + a1);
        }
        for (int i = 0; i < DISC_SIM_N; i++) {
            g_su[i] = (pdt_real_t)disc_u[DISC_SIM_N * s + i];
            g_sym[i] = (pdt_real_t)disc_ymeas[DISC_SIM_N * s + i];
        }
        canary_fill(g_sy + DISC_SIM_N, CANARY_COUNT);
        canary_fill(g_syh + DISC_SIM_N, CANARY_COUNT);
        bool ok = pdt_discrete_simulate(&d, g_su, DISC_SIM_N, g_sy) == PDT_OK;
        ok = pdt_discrete_predict(&d, g_su, g_sym, DISC_SIM_N, g_syh) == PDT_OK && ok;
        ok = canary_intact(g_sy + DISC_SIM_N, CANARY_COUNT) &&
             canary_intact(g_syh + DISC_SIM_N, CANARY_COUNT) && ok;
        double snr_s = snr_db(g_sy, &disc_ysim[DISC_SIM_N * s], DISC_SIM_N);
        double snr_p = snr_db(g_syh, &disc_yhat[DISC_SIM_N * s], DISC_SIM_N);
        ok = ok && snr_s >= SIM_SNR_DB && snr_p >= SIM_SNR_DB;
        tline_t l;
        tl_init(&l);
        tl_str(&l, "dmodel case ");
        tl_int(&l, c);
        tl_str(&l, " (order ");
        tl_uint(&l, d.order);
        tl_str(&l, ", delay ");
        tl_uint(&l, d.delay);
        tl_str(&l, "): SNR simulate ");
        tl_num(&l, snr_s, 4);
        tl_str(&l, " dB, predict ");
        tl_num(&l, snr_p, 4);
        tl_str(&l, " dB (min ");
        tl_num(&l, SIM_SNR_DB, 3);
        tl_str(&l, ")");
        failed += t_verdict(ok, &l);
    }
    return failed;
}

int target_check_discrete(void)
{
    return check_coefficients() + check_simulation();
}

/* ---- Costs ------------------------------------------------------------- */

#define COST_NMAX       600u
#define COST_WORK_REALS (PDT_COST_WORKSPACE_SIZE(COST_NMAX) / sizeof(pdt_real_t))

static pdt_real_t g_cu[COST_NMAX];
static pdt_real_t g_cy[COST_NMAX];
static pdt_real_t g_cw[COST_NMAX + 1u];
static pdt_real_t g_cwork[COST_WORK_REALS + CANARY_COUNT];

static void cost_config(const cost_vec_set_t *s, pdt_cost_config_t *cfg)
{
    VECTOR_COST_CONFIG(cfg, s);
    cfg->weights = g_cw;
}

static bool cost_init(pdt_cost_t *c, const pdt_cost_config_t *cfg, size_t n)
{
    size_t ws = pdt_cost_workspace_size(cfg, n);
    size_t reals = ws / sizeof(pdt_real_t);
    if (ws > sizeof g_cwork - CANARY_COUNT * sizeof(pdt_real_t)) {
        return false;
    }
    canary_fill(g_cwork + reals, CANARY_COUNT);
    return pdt_cost_init(c, cfg, g_cu, g_cy, n, g_cwork, ws) == PDT_OK &&
           canary_intact(g_cwork + reals, CANARY_COUNT);
}

/* One cost value against the reference: updates the worst error, false
 * when the call failed or the value is out of tolerance. */
static bool cost_ok(pdt_status_t st, pdt_real_t got, double want, double *worst)
{
    double e = rel_err((double)got, want);
    *worst = fmax(*worst, e);
    return st == PDT_OK && e <= COST_RTOL;
}

/* Time costs (prediction and simulation, fractional and integer delay,
 * with and without the offset) of the reference's discrete models. */
static bool cost_set_time(const cost_vec_set_t *s, double *worst)
{
    pdt_cost_config_t cfg;
    bool ok = true;
    cost_config(s, &cfg);
    cfg.use_frequency = false;
    for (int ofs = 0; ofs < 2; ofs++) {
        pdt_cost_t c;
        cfg.estimate_offset = ofs != 0;
        if (!cost_init(&c, &cfg, s->n)) {
            return false;
        }
        for (size_t i = 0; i < s->ncand; i++) {
            pdt_discrete_t df = vector_dmodel(s->kind[i], s->delay_frac[i], s->coef_frac + 7u * i);
            pdt_discrete_t di = vector_dmodel(s->kind[i], s->delay_int[i], s->coef_int + 7u * i);
            const double *want = s->cost + COST_NCOL * i;
            pdt_real_t v = 0;
            pdt_status_t st = pdt_cost_prediction(&c, &df, &v);
            ok = cost_ok(st, v, want[COST_COL_PRED_FRAC + ofs], worst) && ok;
            st = pdt_cost_simulation(&c, &df, &v);
            ok = cost_ok(st, v, want[COST_COL_SIM_FRAC + ofs], worst) && ok;
            st = pdt_cost_prediction(&c, &di, &v);
            ok = cost_ok(st, v, want[COST_COL_PRED_INT + ofs], worst) && ok;
            st = pdt_cost_simulation(&c, &di, &v);
            ok = cost_ok(st, v, want[COST_COL_SIM_INT + ofs], worst) && ok;
        }
    }
    return ok;
}

/* Cf under the three weightings. */
static bool cost_set_frequency(const cost_vec_set_t *s, double *worst)
{
    static const pdt_weight_kind_t kinds[3] = {PDT_WEIGHT_UNIFORM, PDT_WEIGHT_BAND,
                                               PDT_WEIGHT_CUSTOM};
    pdt_cost_config_t cfg;
    bool ok = true;
    cost_config(s, &cfg);
    for (size_t wk = 0; wk < 3u; wk++) {
        pdt_cost_t c;
        cfg.weight = kinds[wk];
        if (!cost_init(&c, &cfg, s->n) || c.nf != s->nf) {
            return false;
        }
        for (size_t i = 0; i < s->ncand; i++) {
            pdt_model_t m = vector_model(s->kind[i], s->param + 4u * i);
            pdt_real_t v = 0;
            pdt_status_t st = pdt_cost_frequency(&c, &m, &v);
            ok = cost_ok(st, v, s->cost[COST_NCOL * i + COST_COL_CF_UNIFORM + wk], worst) && ok;
        }
    }
    return ok;
}

/* pdt_cost_eval of the continuous models with the paper's combined cost:
 * A (simulation, fractional delay, offset, uniform weights) and B
 * (prediction, integer delay, band weights). */
static bool cost_set_combined(const cost_vec_set_t *s, double *worst)
{
    bool ok = true;
    for (int which = 0; which < 2; which++) {
        pdt_cost_config_t cfg;
        pdt_cost_t c;
        cost_config(s, &cfg);
        cfg.kind = PDT_COST_COMBINED;
        cfg.time_kind = which == 0 ? PDT_COST_SIMULATION : PDT_COST_PREDICTION;
        cfg.delay_mode = which == 0 ? PDT_DELAY_FRACTIONAL : PDT_DELAY_INTEGER;
        cfg.estimate_offset = which == 0;
        cfg.phi_t = (pdt_real_t)(which == 0 ? COST_PHI_A_T : COST_PHI_B_T);
        cfg.phi_f = (pdt_real_t)(which == 0 ? COST_PHI_A_F : COST_PHI_B_F);
        cfg.weight = which == 0 ? PDT_WEIGHT_UNIFORM : PDT_WEIGHT_BAND;
        if (!cost_init(&c, &cfg, s->n)) {
            return false;
        }
        for (size_t i = 0; i < s->ncand; i++) {
            pdt_model_t m = vector_model(s->kind[i], s->param + 4u * i);
            pdt_real_t v = 0;
            pdt_status_t st = pdt_cost_eval(&c, &m, &v);
            size_t col = which == 0 ? COST_COL_COMB_A : COST_COL_COMB_B;
            ok = cost_ok(st, v, s->cost[COST_NCOL * i + col], worst) && ok;
        }
    }
    return ok;
}

int target_check_cost(void)
{
    int failed = 0;
    for (size_t si = 0; si < sizeof cost_vec_sets / sizeof cost_vec_sets[0]; si++) {
        const cost_vec_set_t *s = &cost_vec_sets[si];
        double wt = 0.0, wf = 0.0, wc = 0.0;
        bool ok = s->n <= COST_NMAX;
        if (ok) {
            for (size_t k = 0; k < s->n; k++) {
                g_cu[k] = (pdt_real_t)s->u[k];
                g_cy[k] = (pdt_real_t)s->y[k];
            }
            for (size_t k = 0; k <= s->nf / 2u; k++) {
                g_cw[k] = (pdt_real_t)s->weights[k];
            }
            ok = cost_set_time(s, &wt);
            ok = cost_set_frequency(s, &wf) && ok;
            ok = cost_set_combined(s, &wc) && ok;
        }
        tline_t l;
        tl_init(&l);
        tl_str(&l, "cost ");
        tl_str(&l, s->name);
        tl_str(&l, " (n=");
        tl_uint(&l, s->n);
        tl_str(&l, ", ");
        tl_uint(&l, s->ncand);
        tl_str(&l, " models): worst relative error time ");
        tl_num(&l, wt, 3);
        tl_str(&l, ", frequency ");
        tl_num(&l, wf, 3);
        tl_str(&l, ", combined ");
        tl_num(&l, wc, 3);
        tl_str(&l, " (max ");
        tl_num(&l, COST_RTOL, 2);
        tl_str(&l, ")");
        failed += t_verdict(ok, &l);
    }
    return failed;
}
