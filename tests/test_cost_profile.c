/*
 * Tests of the cost module's whole-record scoring, gain/offset profile
 * (pdt_cost_profile) and simulation in engineering units
 * (pdt_cost_simulate) against the numpy reference
 * (tests/vectors/cost_profile_vectors.h, written by
 * tools/vectorgen/cost_profile.py), plus properties: the profile's cost is
 * the cost of the rebuilt model, its gain beats gains 1% away, the offset
 * reproduces the profiled time cost, pdt_cost_simulate is
 * pdt_discrete_simulate plus y0, whole_record moves the TOO_SHORT threshold;
 * and every bad-input status with outputs left untouched.
 */
#include "pdt_cost_engine.h"
#include "sim_rng.h"
#include "test_util.h"

#include "cost_accuracy_vectors.h"
#include "cost_profile_vectors.h"

/* Relative tolerance against the double reference. Float: the data are
 * exact in float, the configuration (Ts, bounds) is not always; the
 * measured worst cases are printed by the vector tests. */
#if PDT_REAL_DOUBLE
#define CPV_RTOL 1e-9
#else
#define CPV_RTOL 1e-4
#endif

#define CPV_NMAX 600u

/* The loose bound of a candidate far worse than the hint's cost. */
#if PDT_REAL_DOUBLE
#define CPV_RTOL_POOR 1e-7
#else
#define CPV_RTOL_POOR 2e-3
#endif

/* Accuracy over records up to 10^4 samples and scales 1e-30 .. 1e30; the
 * float bound is that of the short vectors. */
#if PDT_REAL_DOUBLE
#define CAV_RTOL 1e-9
#else
#define CAV_RTOL 1e-4
#endif
#define CPV_NSETS      (sizeof cpv_sets / sizeof cpv_sets[0])
#define CPV_WORK_REALS (PDT_COST_WORKSPACE_SIZE(CPV_NMAX) / sizeof(pdt_real_t))

static pdt_real_t g_u[CPV_NMAX];
static pdt_real_t g_y[CPV_NMAX];
static pdt_real_t g_dev[CPV_NMAX];
static pdt_real_t g_ref[CPV_NMAX];
static pdt_real_t g_scratch[CPV_NMAX + CANARY_COUNT];
static pdt_real_t g_ysim[CPV_NMAX + CANARY_COUNT];
static pdt_real_t g_work[CPV_WORK_REALS + CANARY_COUNT];
/* A second cost object needs its own normalised record. */
static pdt_real_t g_work2[2u * CPV_NMAX];

static void load_set(const cpv_set_t *s)
{
    assert_true(s->n <= CPV_NMAX);
    for (size_t k = 0; k < s->n; k++) {
        g_u[k] = (pdt_real_t)s->u[k];
        g_y[k] = (pdt_real_t)s->y[k];
    }
}

/* Largest |y - y0| of the set: the scale of offsets. */
static double y_scale(const cpv_set_t *s)
{
    double m = 0.0;
    for (size_t k = 0; k < s->n; k++) {
        m = fmax(m, fabs(s->y[k] - s->y0));
    }
    return m;
}

static void base_config(const cpv_set_t *s, pdt_cost_config_t *cfg)
{
    VECTOR_COST_CONFIG(cfg, s);
}

static void apply_config(const cpv_config_t *v, pdt_cost_config_t *cfg)
{
    cfg->kind = (pdt_cost_kind_t)v->kind;
    cfg->time_kind = (pdt_cost_kind_t)v->time_kind;
    cfg->delay_mode = (pdt_delay_mode_t)v->mode;
    cfg->whole_record = (v->whole_record != 0);
    cfg->estimate_offset = (v->estimate_offset != 0);
    cfg->phi_t = (pdt_real_t)v->phi_t;
    cfg->phi_f = (pdt_real_t)v->phi_f;
    cfg->weight = (pdt_weight_kind_t)v->weight;
    cfg->use_frequency = true;
}

/* Initialises c on the loaded record, checking nothing is written past
 * the workspace. */
static void init_ok(pdt_cost_t *c, const pdt_cost_config_t *cfg, size_t n)
{
    size_t ws = pdt_cost_workspace_size(cfg, n);
    size_t reals = ws / sizeof(pdt_real_t);
    assert_true(reals <= CPV_WORK_REALS);
    canary_fill(g_work + reals, CANARY_COUNT);
    assert_int_equal(pdt_cost_init(c, cfg, g_u, g_y, n, g_work, ws), PDT_OK);
    canary_check(g_work + reals, CANARY_COUNT);
}

static pdt_discrete_t dmodel_of(int order, int delay, const double *coef)
{
    return vector_dmodel(order, delay, coef);
}

/* Shape i of set s, its gain multiplied by g. */
static pdt_model_t model_of(const cpv_set_t *s, size_t i, double g)
{
    const double *p = s->param + 4u * i;
    const double q[4] = {g * p[0], p[1], p[2], p[3]};
    return vector_model(s->kind[i], q);
}

/* Scales a model's gain in the real type (the profile's gain multiplies
 * the shape's gain). */
static pdt_model_t with_gain(pdt_model_t m, pdt_real_t g)
{
    if (m.kind == PDT_MODEL_FOPDT) {
        m.p.fopdt.K *= g;
    } else {
        m.p.sopdt.k *= g;
    }
    return m;
}

/* |got - want| <= rtol (|want| + floor); tracks the worst error relative
 * to |want| + floor. */
static void check_val(double got, double want, double rtol, double floor, double *worst,
                      const char *set, size_t shape, const char *cfg, const char *what)
{
    double e = (got == want) ? 0.0 : fabs(got - want) / (fabs(want) + floor);
    if (e > *worst) {
        *worst = e;
    }
    if (!(e <= rtol)) {
        fail_msg("%s shape %zu %s %s: got %.17g want %.17g (err %.3g > %.3g)", set, shape, cfg,
                 what, got, want, e, rtol);
    }
}

/* ---- vectors ---- */

static void test_vectors_whole_record(void **state)
{
    double worst = 0.0;
    (void)state;
    for (size_t si = 0; si < CPV_NSETS; si++) {
        const cpv_set_t *s = &cpv_sets[si];
        pdt_cost_config_t cfg;
        load_set(s);
        base_config(s, &cfg);
        cfg.use_frequency = false;
        cfg.whole_record = true;
        for (int ofs = 0; ofs < 2; ofs++) {
            pdt_cost_t c;
            cfg.estimate_offset = (ofs != 0);
            init_ok(&c, &cfg, s->n);
            for (size_t i = 0; i < s->nshape; i++) {
                pdt_discrete_t dm[2];
                dm[0] = dmodel_of(s->kind[i], s->delay_frac[i], s->coef_frac + 7u * i);
                dm[1] = dmodel_of(s->kind[i], s->delay_int[i], s->coef_int + 7u * i);
                for (size_t j = 0; j < 2; j++) {
                    /* whole[]: per model pred, pred_ofs, sim, sim_ofs;
                     * fractional models first, then integer ones. */
                    const double *want = s->whole + 4u * (j * s->nshape + i);
                    pdt_real_t v[CANARY_COUNT + 1];
                    canary_fill(v + 1, CANARY_COUNT);
                    assert_int_equal(pdt_cost_prediction(&c, &dm[j], v), PDT_OK);
                    check_val((double)v[0], want[ofs], CPV_RTOL, 0.0, &worst, s->name, i,
                              j ? "int" : "frac", "whole prediction");
                    assert_int_equal(pdt_cost_simulation(&c, &dm[j], v), PDT_OK);
                    check_val((double)v[0], want[2 + ofs], CPV_RTOL, 0.0, &worst, s->name, i,
                              j ? "int" : "frac", "whole simulation");
                    canary_check(v + 1, CANARY_COUNT);
                }
            }
        }
    }
    print_message("worst relative error, whole-record time costs: %.3g\n", worst);
}

/* Worst errors of the profile against the vectors: cost, gain, offset
 * (relative to |offset| + the output's range), ct, cf. */
static double g_worst[5];

/* The cost of set si under configuration ci, its record loaded. */
static const cpv_config_t *open_case(const cpv_set_t *s, size_t ci, pdt_cost_t *c)
{
    const cpv_config_t *v = &cpv_configs[ci];
    pdt_cost_config_t cfg;
    load_set(s);
    base_config(s, &cfg);
    apply_config(v, &cfg);
    init_ok(c, &cfg, s->n);
    return v;
}

static void test_vectors_profile(void **state)
{
    (void)state;
    memset(g_worst, 0, sizeof g_worst);
    for (size_t si = 0; si < CPV_NSETS; si++) {
        const cpv_set_t *s = &cpv_sets[si];
        const double ys = y_scale(s);
        for (size_t ci = 0; ci < CPV_NCFG; ci++) {
            pdt_cost_t c;
            const cpv_config_t *v = open_case(s, ci, &c);
            for (size_t i = 0; i < s->nshape; i++) {
                const cpv_result_t *w = &s->result[i * CPV_NCFG + ci];
                pdt_model_t m = model_of(s, i, 1.0);
                pdt_cost_profile_t r;
                double gain;
                canary_fill(g_scratch + s->n, CANARY_COUNT);
                assert_int_equal(pdt_cost_profile(&c, &m, (pdt_real_t)w->gain_min,
                                                  (pdt_real_t)w->gain_max, g_scratch, &r),
                                 PDT_OK);
                canary_check(g_scratch + s->n, CANARY_COUNT);
                /* A cost blind to the gain's sign: the sign is arbitrary. */
                gain = w->sign_free ? fabs((double)r.gain) : (double)r.gain;
                if (w->gain_min != 0.0 || w->gain_max != 0.0) {
                    assert_true((double)r.gain >= (double)(pdt_real_t)w->gain_min &&
                                (double)r.gain <= (double)(pdt_real_t)w->gain_max);
                }
                check_val((double)r.cost, w->cost, CPV_RTOL, 0.0, &g_worst[0], s->name, i, v->name,
                          "cost");
                check_val(gain, w->sign_free ? fabs(w->gain) : w->gain, CPV_RTOL, 0.0, &g_worst[1],
                          s->name, i, v->name, "gain");
                check_val((double)r.offset, w->offset, CPV_RTOL, ys, &g_worst[2], s->name, i,
                          v->name, "offset");
                check_val((double)r.ct, w->ct, CPV_RTOL, 0.0, &g_worst[3], s->name, i, v->name,
                          "ct");
                check_val((double)r.cf, w->cf, CPV_RTOL, 0.0, &g_worst[4], s->name, i, v->name,
                          "cf");
            }
        }
    }
    print_message("worst relative errors, profile: cost %.3g gain %.3g offset %.3g "
                  "(of the output range) ct %.3g cf %.3g\n",
                  g_worst[0], g_worst[1], g_worst[2], g_worst[3], g_worst[4]);
}

/* pdt_cost_profile_many, four shapes (or the rest) at a time with each
 * shape's own bounds, and pdt_cost_profile_hint with poor references,
 * against the same reference values. */
static void test_vectors_many_and_hints(void **state)
{
    double worst = 0.0;
    (void)state;
    for (size_t si = 0; si < CPV_NSETS; si++) {
        const cpv_set_t *s = &cpv_sets[si];
        const double ys = y_scale(s);
        for (size_t ci = 0; ci < CPV_NCFG; ci++) {
            pdt_cost_t c;
            const cpv_config_t *v = open_case(s, ci, &c);
            for (size_t i0 = 0; i0 < s->nshape; i0 += PDT_COST_MANY) {
                size_t cnt = s->nshape - i0 < PDT_COST_MANY ? s->nshape - i0 : PDT_COST_MANY;
                pdt_model_t m[PDT_COST_MANY];
                pdt_real_t lo[PDT_COST_MANY], hi[PDT_COST_MANY];
                pdt_cost_profile_t r[PDT_COST_MANY + 1u];
                r[cnt].cost = (pdt_real_t)-1.0;
                for (size_t k = 0; k < cnt; k++) {
                    const cpv_result_t *w = &s->result[(i0 + k) * CPV_NCFG + ci];
                    m[k] = model_of(s, i0 + k, 1.0);
                    lo[k] = (pdt_real_t)w->gain_min;
                    hi[k] = (pdt_real_t)w->gain_max;
                }
                /* a reference fit far off (the first shape's gain, doubled) */
                const pdt_cost_hint_t far = {(pdt_real_t)(2.0 * s->result[i0 * CPV_NCFG + ci].gain),
                                             (pdt_real_t)ys, 0};
                assert_int_equal(pdt_cost_profile_many(&c, m, cnt, lo, hi, &far, g_scratch, r),
                                 PDT_OK);
                assert_true(r[cnt].cost == (pdt_real_t)-1.0);
                for (size_t k = 0; k < cnt; k++) {
                    const cpv_result_t *w = &s->result[(i0 + k) * CPV_NCFG + ci];
                    double gain = w->sign_free ? fabs((double)r[k].gain) : (double)r[k].gain;
                    pdt_cost_profile_t h;
                    check_val((double)r[k].cost, w->cost, CPV_RTOL, 0.0, &worst, s->name, i0 + k,
                              v->name, "many cost");
                    check_val(gain, w->sign_free ? fabs(w->gain) : w->gain, CPV_RTOL, 0.0, &worst,
                              s->name, i0 + k, v->name, "many gain");
                    check_val((double)r[k].offset, w->offset, CPV_RTOL, ys, &worst, s->name, i0 + k,
                              v->name, "many offset");
                    /* the exact reference and a reference at minus the gain */
                    for (int sgn = -1; sgn <= 1; sgn += 2) {
                        const pdt_cost_hint_t ref = {(pdt_real_t)(sgn * w->gain),
                                                     (pdt_real_t)w->offset, 0};
                        assert_int_equal(
                            pdt_cost_profile_hint(&c, &m[k], lo[k], hi[k], &ref, g_scratch, &h),
                            PDT_OK);
                        check_val((double)h.cost, w->cost, CPV_RTOL, 0.0, &worst, s->name, i0 + k,
                                  v->name, "hint cost");
                        check_val((double)h.offset, w->offset, CPV_RTOL, ys, &worst, s->name,
                                  i0 + k, v->name, "hint offset");
                        assert_true(fabs((double)h.ncost - (double)r[k].ncost) <=
                                    1e-4 * fabs((double)r[k].ncost));
                    }
                    /* A reference cost far below: every candidate counts as
                     * poor and is scored to the loose bound, in one pass. */
                    const pdt_cost_hint_t poor = {(pdt_real_t)(3.0 * w->gain), 0,
                                                  (pdt_real_t)1e-30};
                    assert_int_equal(
                        pdt_cost_profile_hint(&c, &m[k], lo[k], hi[k], &poor, g_scratch, &h),
                        PDT_OK);
                    assert_close(h.cost, w->cost, CPV_RTOL_POOR, 0.0);
                    /* A reference whose residual overflows: as without one. */
                    const pdt_cost_hint_t wild = {(pdt_real_t)1e30, (pdt_real_t)-1e30, 0};
                    assert_int_equal(
                        pdt_cost_profile_hint(&c, &m[k], lo[k], hi[k], &wild, g_scratch, &h),
                        PDT_OK);
                    check_val((double)h.cost, w->cost, CPV_RTOL, 0.0, &worst, s->name, i0 + k,
                              v->name, "wild hint cost");
                }
            }
            /* Four shapes of one order: the side-by-side pass where the
             * host has one. */
            for (int kind = 1; kind <= 2; kind++) {
                size_t idx[PDT_COST_MANY], cnt = 0;
                pdt_model_t m[PDT_COST_MANY];
                pdt_real_t lo[PDT_COST_MANY], hi[PDT_COST_MANY];
                pdt_cost_profile_t r[PDT_COST_MANY];
                for (size_t j = 0; cnt < PDT_COST_MANY && j < 4u * s->nshape; j++) {
                    if (s->kind[j % s->nshape] == kind) {
                        idx[cnt++] = j % s->nshape;
                    }
                }
                if (cnt == 0) {
                    continue;
                }
                for (size_t k = 0; k < cnt; k++) {
                    const cpv_result_t *w = &s->result[idx[k] * CPV_NCFG + ci];
                    m[k] = model_of(s, idx[k], 1.0);
                    lo[k] = (pdt_real_t)w->gain_min;
                    hi[k] = (pdt_real_t)w->gain_max;
                }
                assert_int_equal(pdt_cost_profile_many(&c, m, cnt, lo, hi, NULL, g_scratch, r),
                                 PDT_OK);
                for (size_t k = 0; k < cnt; k++) {
                    const cpv_result_t *w = &s->result[idx[k] * CPV_NCFG + ci];
                    double gain = w->sign_free ? fabs((double)r[k].gain) : (double)r[k].gain;
                    check_val((double)r[k].cost, w->cost, CPV_RTOL, 0.0, &worst, s->name, idx[k],
                              v->name, "many4 cost");
                    check_val(gain, w->sign_free ? fabs(w->gain) : w->gain, CPV_RTOL, 0.0, &worst,
                              s->name, idx[k], v->name, "many4 gain");
                    check_val((double)r[k].offset, w->offset, CPV_RTOL, ys, &worst, s->name, idx[k],
                              v->name, "many4 offset");
                }
            }
        }
    }
    print_message("worst relative error, profile_many and hinted profiles: %.3g\n", worst);
}

/* m at dead time l Ts. */
static pdt_model_t at_delay(pdt_model_t m, size_t l, pdt_real_t Ts)
{
    const pdt_real_t Td = (pdt_real_t)l * Ts;
    if (m.kind == PDT_MODEL_FOPDT) {
        m.p.fopdt.Td = Td;
    } else {
        m.p.sopdt.Td = Td;
    }
    return m;
}

/* A shape's whole-sample dead times scored from its stored response
 * (pdt_cost_response, pdt_cost_profile_shift), on every SIMULATION
 * configuration of the vectors: pdt_cost_profile_many's profiles of the
 * same shapes at those dead times, bit for bit where the delay is taken
 * in whole samples (PDT_DELAY_INTEGER) and within the vectors' tolerance
 * otherwise (there a dead time of l Ts can round to a fraction of a
 * sample); and at the shape's own dead time under PDT_DELAY_INTEGER, the
 * numpy reference's profile. One to four delays a call, with and
 * without a reference fit. */
static void test_shift_profiles(void **state)
{
    double worst = 0.0;
    size_t checked = 0u;
    (void)state;
    for (size_t si = 0; si < CPV_NSETS; si++) {
        const cpv_set_t *s = &cpv_sets[si];
        const double ys = y_scale(s);
        for (size_t ci = 0; ci < CPV_NCFG; ci++) {
            if (cpv_configs[ci].kind != (int)PDT_COST_SIMULATION) {
                continue;
            }
            pdt_cost_t c;
            const cpv_config_t *v = open_case(s, ci, &c);
            const bool whole = c.cfg.delay_mode == PDT_DELAY_INTEGER;
            const pdt_real_t Ts = c.cfg.Ts;
            for (size_t i = 0; i < s->nshape; i++) {
                const cpv_result_t *w = &s->result[i * CPV_NCFG + ci];
                const pdt_model_t m = model_of(s, i, 1.0);
                const pdt_real_t lo = (pdt_real_t)w->gain_min, hi = (pdt_real_t)w->gain_max;
                const double own = floor((double)pdt_model_dead_time(&m) / (double)Ts + 0.5);
                size_t delay[PDT_COST_MANY];
                pdt_model_t shapes[PDT_COST_MANY];
                pdt_real_t los[PDT_COST_MANY], his[PDT_COST_MANY];
                canary_fill(g_scratch + s->n, CANARY_COUNT);
                assert_int_equal(pdt_cost_response(&c, &m, g_scratch), PDT_OK);
                canary_check(g_scratch + s->n, CANARY_COUNT);
                for (size_t k = 0; k < PDT_COST_MANY; k++) {
                    /* the shape's own delay first, then three around it */
                    size_t l = (size_t)own + (k == 0u ? 0u : 2u * k - 1u);
                    l = l < c.cfg.delay_min ? c.cfg.delay_min : l;
                    l = l > c.cfg.delay_max ? c.cfg.delay_max : l;
                    delay[k] = l;
                    shapes[k] = at_delay(m, l, Ts);
                    los[k] = lo;
                    his[k] = hi;
                }
                const pdt_cost_hint_t hints[2] = {
                    {0, 0, 0}, {(pdt_real_t)w->gain, (pdt_real_t)w->offset, (pdt_real_t)0}};
                for (size_t h = 0; h < 2u; h++) {
                    for (size_t cnt = 1; cnt <= PDT_COST_MANY; cnt++) {
                        pdt_cost_profile_t r[PDT_COST_MANY + 1u], q[PDT_COST_MANY];
                        r[cnt].cost = (pdt_real_t)-1.0;
                        assert_int_equal(pdt_cost_profile_shift(&c, &m, g_scratch, delay, cnt, lo,
                                                                hi, &hints[h], r),
                                         PDT_OK);
                        assert_true(r[cnt].cost == (pdt_real_t)-1.0);
                        assert_int_equal(
                            pdt_cost_profile_many(&c, shapes, cnt, los, his, &hints[h], g_ysim, q),
                            PDT_OK);
                        for (size_t k = 0; k < cnt; k++) {
                            if (whole) {
                                assert_true(r[k].ncost == q[k].ncost && r[k].gain == q[k].gain &&
                                            r[k].offset == q[k].offset);
                            }
                            check_val((double)r[k].cost, (double)q[k].cost, CPV_RTOL, 0.0, &worst,
                                      s->name, i, v->name, "shift cost");
                            check_val((double)r[k].offset, (double)q[k].offset, CPV_RTOL, ys,
                                      &worst, s->name, i, v->name, "shift offset");
                            checked++;
                        }
                        if (whole && delay[0] == (size_t)own) {
                            double gain =
                                w->sign_free ? fabs((double)r[0].gain) : (double)r[0].gain;
                            check_val((double)r[0].cost, w->cost, CPV_RTOL, 0.0, &worst, s->name, i,
                                      v->name, "shift cost (reference)");
                            check_val(gain, w->sign_free ? fabs(w->gain) : w->gain, CPV_RTOL, 0.0,
                                      &worst, s->name, i, v->name, "shift gain (reference)");
                            check_val((double)r[0].offset, w->offset, CPV_RTOL, ys, &worst, s->name,
                                      i, v->name, "shift offset (reference)");
                        }
                    }
                }
            }
        }
    }
    assert_true(checked > 0u);
    print_message("pdt_cost_profile_shift: %zu profiles, worst relative error %.3g\n", checked,
                  worst);
}

/* The refusals of pdt_cost_response and pdt_cost_profile_shift leave
 * their outputs untouched. */
static void test_shift_errors(void **state)
{
    const cpv_set_t *s = &cpv_sets[0];
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    const pdt_model_t m = model_of(s, 0, 1.0);
    pdt_cost_profile_t r[PDT_COST_MANY];
    size_t delay[PDT_COST_MANY];
    (void)state;
    load_set(s);
    base_config(s, &cfg);
    apply_config(&cpv_configs[1], &cfg); /* SIMULATION, whole samples */
    init_ok(&c, &cfg, s->n);
    for (size_t k = 0; k < PDT_COST_MANY; k++) {
        delay[k] = c.cfg.delay_min + k;
    }
    memset(r, 0x5a, sizeof r);
    for (size_t k = 0; k < s->n; k++) {
        g_ref[k] = (pdt_real_t)0.25;
    }
    assert_int_equal(pdt_cost_response(NULL, &m, g_ref), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_response(&c, NULL, g_ref), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_response(&c, &m, NULL), PDT_ERR_ARG);
    pdt_model_t bad = m;
    bad.kind = (pdt_model_kind_t)99;
    assert_int_equal(pdt_cost_response(&c, &bad, g_ref), PDT_ERR_ARG);
    for (size_t k = 0; k < s->n; k++) {
        assert_true(g_ref[k] == (pdt_real_t)0.25);
    }
    assert_int_equal(pdt_cost_response(&c, &m, g_scratch), PDT_OK);
    assert_int_equal(pdt_cost_profile_shift(&c, &m, g_scratch, delay, 0u, 0, 0, NULL, r),
                     PDT_ERR_ARG);
    assert_int_equal(
        pdt_cost_profile_shift(&c, &m, g_scratch, delay, PDT_COST_MANY + 1u, 0, 0, NULL, r),
        PDT_ERR_ARG);
    assert_int_equal(pdt_cost_profile_shift(NULL, &m, g_scratch, delay, 1u, 0, 0, NULL, r),
                     PDT_ERR_ARG);
    assert_int_equal(pdt_cost_profile_shift(&c, &bad, g_scratch, delay, 1u, 0, 0, NULL, r),
                     PDT_ERR_ARG);
    assert_int_equal(pdt_cost_profile_shift(&c, &m, NULL, delay, 1u, 0, 0, NULL, r), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_profile_shift(&c, &m, g_scratch, NULL, 1u, 0, 0, NULL, r),
                     PDT_ERR_ARG);
    assert_int_equal(pdt_cost_profile_shift(&c, &m, g_scratch, delay, 1u, 2, 1, NULL, r),
                     PDT_ERR_BOUNDS);
    assert_int_equal(
        pdt_cost_profile_shift(&c, &m, g_scratch, delay, 1u, (pdt_real_t)NAN, 1, NULL, r),
        PDT_ERR_ARG);
    /* a delay beyond the cost's bound, in the last place */
    delay[PDT_COST_MANY - 1u] = c.cfg.delay_max + 1u;
    assert_int_equal(pdt_cost_profile_shift(&c, &m, g_scratch, delay, PDT_COST_MANY, 0, 0, NULL, r),
                     PDT_ERR_ARG);
    for (size_t k = 0; k < sizeof r; k++) {
        assert_int_equal(((const unsigned char *)r)[k], 0x5a);
    }
    /* not a SIMULATION cost: the prediction error */
    apply_config(&cpv_configs[3], &cfg);
    init_ok(&c, &cfg, s->n);
    assert_int_equal(pdt_cost_response(&c, &m, g_ref), PDT_ERR_ARG);
    delay[PDT_COST_MANY - 1u] = c.cfg.delay_min;
    assert_int_equal(pdt_cost_profile_shift(&c, &m, g_scratch, delay, 1u, 0, 0, NULL, r),
                     PDT_ERR_ARG);
    for (size_t k = 0; k < s->n; k++) {
        assert_true(g_ref[k] == (pdt_real_t)0.25);
    }
}

/* The refusals of pdt_cost_profile_many leave out untouched. */
static void test_many_errors(void **state)
{
    const cpv_set_t *s = &cpv_sets[0];
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    pdt_model_t m[PDT_COST_MANY];
    pdt_real_t lo[PDT_COST_MANY] = {0}, hi[PDT_COST_MANY] = {0};
    pdt_cost_profile_t r[PDT_COST_MANY];
    (void)state;
    load_set(s);
    base_config(s, &cfg);
    apply_config(&cpv_configs[0], &cfg);
    init_ok(&c, &cfg, s->n);
    for (size_t k = 0; k < PDT_COST_MANY; k++) {
        m[k] = model_of(s, k % s->nshape, 1.0);
    }
    memset(r, 0x5a, sizeof r);
    assert_int_equal(pdt_cost_profile_many(&c, m, 0u, lo, hi, NULL, g_scratch, r), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_profile_many(&c, m, PDT_COST_MANY + 1u, lo, hi, NULL, g_scratch, r),
                     PDT_ERR_ARG);
    assert_int_equal(pdt_cost_profile_many(NULL, m, 1u, lo, hi, NULL, g_scratch, r), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_profile_many(&c, NULL, 1u, lo, hi, NULL, g_scratch, r), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_profile_many(&c, m, 1u, NULL, hi, NULL, g_scratch, r), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_profile_many(&c, m, 1u, lo, hi, NULL, NULL, r), PDT_ERR_ARG);
    lo[2] = 2;
    hi[2] = 1;
    assert_int_equal(pdt_cost_profile_many(&c, m, PDT_COST_MANY, lo, hi, NULL, g_scratch, r),
                     PDT_ERR_BOUNDS);
    lo[2] = 0;
    hi[2] = 0;
    m[3].kind = (pdt_model_kind_t)99;
    assert_int_equal(pdt_cost_profile_many(&c, m, PDT_COST_MANY, lo, hi, NULL, g_scratch, r),
                     PDT_ERR_ARG);
    for (size_t k = 0; k < sizeof r; k++) {
        assert_int_equal(((const unsigned char *)r)[k], 0x5a);
    }
}

/* ---- accuracy over long records and data scales ---- */

#define CAV_NMAX 10000u
static pdt_real_t g_au[CAV_NMAX];
static pdt_real_t g_ay[CAV_NMAX];
static pdt_real_t g_awork[2u * CAV_NMAX];
static pdt_real_t g_ascratch[CAV_NMAX];

/* The record of a case, rebuilt with the generator's double arithmetic. */
static void cav_record(const cav_case_t *v)
{
    /* The stream tools/vectorgen/cost_accuracy.py made the references'
     * records with. */
    sim_rng64_t st = sim_rng64_seed(v->seed);
    double x = 0.0;
    static double ud[CAV_NMAX];
    assert_true(v->n <= CAV_NMAX);
    for (size_t k = 0; k < v->n; k += v->hold) {
        double level = (sim_rng64_uniform(&st) < 0.5) ? 1.0 : -1.0;
        for (size_t j = k; j < k + v->hold && j < v->n; j++) {
            ud[j] = level;
        }
    }
    for (size_t k = 0; k < v->n; k++) {
        double sum = 0.0;
        for (int i = 0; i < 4; i++) {
            sum += sim_rng64_uniform(&st);
        }
        double noise = v->amp * (sum - 2.0);
        double uin = (k >= 1u + CAV_PLANT_L) ? ud[k - 1u - CAV_PLANT_L] : 0.0;
        x = v->a * x + v->b * uin;
        g_au[k] = (pdt_real_t)(float)(v->su * ud[k] + v->uoff);
        g_ay[k] = (pdt_real_t)(float)(v->sy * (x + noise) + v->yoff);
    }
}

static void test_accuracy_scales(void **state)
{
    double worst[3] = {0.0, 0.0, 0.0};
    (void)state;
    for (size_t ci = 0; ci < sizeof cav_cases / sizeof cav_cases[0]; ci++) {
        const cav_case_t *v = &cav_cases[ci];
        pdt_cost_config_t cfg;
        pdt_cost_t c;
        double cw[3] = {0.0, 0.0, 0.0};
        cav_record(v);
        assert_true((double)g_au[0] == v->u0 && (double)g_ay[0] == v->y0);
        pdt_cost_config_default(&cfg);
        cfg.Ts = (pdt_real_t)CAV_TS;
        cfg.u0 = g_au[0];
        cfg.y0 = g_ay[0];
        cfg.delay_max = CAV_DELAY_MAX;
        cfg.kind = PDT_COST_SIMULATION;
        cfg.whole_record = true;
        cfg.use_frequency = false;
        assert_int_equal(pdt_cost_init(&c, &cfg, g_au, g_ay, v->n, g_awork, sizeof g_awork),
                         PDT_OK);
        for (size_t i = 0; i < CAV_NSHAPE; i++) {
            const double q[4] = {cav_shape_param[4u * i], cav_shape_param[4u * i + 1u],
                                 cav_shape_param[4u * i + 2u], cav_shape_param[4u * i + 3u]};
            pdt_model_t m[PDT_COST_MANY];
            pdt_real_t lo[PDT_COST_MANY] = {0}, hi[PDT_COST_MANY] = {0};
            pdt_cost_profile_t r[PDT_COST_MANY + 2u];
            const double ncost = ldexp(v->cost[i], -2 * c.y_exp);
            for (size_t k = 0; k < PDT_COST_MANY; k++) {
                m[k] = vector_model(cav_shape_kind[i], q);
            }
            /* without a reference, with the exact one, and four at a time
             * with one half the gain off */
            assert_int_equal(pdt_cost_profile(&c, &m[0], 0, 0, g_ascratch, &r[0]), PDT_OK);
            const pdt_cost_hint_t exact = {(pdt_real_t)v->gain[i], (pdt_real_t)v->offset[i], 0};
            const pdt_cost_hint_t off = {(pdt_real_t)(1.5 * v->gain[i]), (pdt_real_t)v->offset[i],
                                         0};
            assert_int_equal(pdt_cost_profile_hint(&c, &m[0], 0, 0, &exact, g_ascratch, &r[1]),
                             PDT_OK);
            assert_int_equal(
                pdt_cost_profile_many(&c, m, PDT_COST_MANY, lo, hi, &off, g_ascratch, &r[2]),
                PDT_OK);
            for (size_t k = 0; k < 3u; k++) {
                cw[0] = fmax(cw[0], rel_err((double)r[k].ncost, ncost));
                /* against the gain or, if larger, the one that spans the
                 * output range with this shape (cost_accuracy.py) */
                cw[1] = fmax(cw[1], fabs((double)r[k].gain - v->gain[i]) /
                                        fmax(fabs(v->gain[i]), v->gain_scale[i]));
                cw[2] = fmax(cw[2], fabs((double)r[k].offset - v->offset[i]) / v->yrange);
                if (ncost * ldexp(1.0, 2 * c.y_exp) < 1e38 &&
                    ncost * ldexp(1.0, 2 * c.y_exp) > 1e-37) {
                    cw[0] = fmax(cw[0], rel_err((double)r[k].cost, v->cost[i]));
                }
            }
        }
        print_message("accuracy n %5zu noise %-6g su %-6g sy %-6g: cost %.2g gain %.2g "
                      "offset %.2g\n",
                      v->n, v->amp, v->su, v->sy, cw[0], cw[1], cw[2]);
        for (int k = 0; k < 3; k++) {
            worst[k] = fmax(worst[k], cw[k]);
        }
    }
    print_message("worst relative errors against the double reference: cost %.3g gain %.3g "
                  "(of the gain or the one spanning max |y - y0|) offset %.3g (of max |y - y0|)\n",
                  worst[0], worst[1], worst[2]);
    assert_true(worst[0] <= CAV_RTOL);
    assert_true(worst[1] <= CAV_RTOL);
    assert_true(worst[2] <= CAV_RTOL);
}

static void test_vectors_simulate(void **state)
{
    double worst_snr = 400.0;
    (void)state;
    for (size_t si = 0; si < CPV_NSETS; si++) {
        const cpv_set_t *s = &cpv_sets[si];
        pdt_cost_config_t cfg;
        pdt_cost_t c;
        load_set(s);
        base_config(s, &cfg);
        cfg.use_frequency = false;
        init_ok(&c, &cfg, s->n);
        for (size_t j = 0; j < 2; j++) {
            pdt_discrete_t d = dmodel_of(s->sim_order[j], s->sim_delay[j], s->sim_coef + 7u * j);
            const double *want = s->ysim + j * s->n;
            double snr;
            canary_fill(g_ysim + s->n, CANARY_COUNT);
            assert_int_equal(pdt_cost_simulate(&c, &d, g_ysim), PDT_OK);
            canary_check(g_ysim + s->n, CANARY_COUNT);
            /* Engineering units: SNR of the deviation from y0, plus a
             * sample-wise check of the absolute values. */
            for (size_t k = 0; k < s->n; k++) {
                g_ref[k] = (pdt_real_t)((double)g_ysim[k] - s->y0);
                assert_close(g_ysim[k], want[k], CPV_RTOL, CPV_RTOL * y_scale(s));
            }
            {
                double dev[CPV_NMAX];
                for (size_t k = 0; k < s->n; k++) {
                    dev[k] = want[k] - s->y0;
                }
                snr = snr_db(g_ref, dev, s->n);
            }
            worst_snr = fmin(worst_snr, snr);
            assert_true(snr >= (PDT_REAL_DOUBLE ? 180.0 : 80.0));
            if (j == 1) {
                /* Delay beyond delay_max: flat at y0 until the input
                 * arrives. */
                for (size_t k = 0; k <= d.delay && k < s->n; k++) {
                    assert_true(g_ysim[k] == (pdt_real_t)s->y0);
                }
            }
        }
    }
    print_message("worst SNR, pdt_cost_simulate: %.1f dB\n", worst_snr);
}

/* ---- properties ---- */

/* Tolerance of a cost recomputed from a rebuilt model: the discretisation
 * of the scaled model rounds differently from the scaled discretisation. */
#if PDT_REAL_DOUBLE
#define CPV_RTOL_REBUILT 1e-8
#else
#define CPV_RTOL_REBUILT 1e-3
#endif

static void test_profile_properties(void **state)
{
    double worst_rebuilt = 0.0, worst_offset = 0.0;
    (void)state;
    for (size_t si = 0; si < CPV_NSETS; si++) {
        const cpv_set_t *s = &cpv_sets[si];
        load_set(s);
        for (size_t ci = 0; ci < CPV_NCFG; ci++) {
            const cpv_config_t *v = &cpv_configs[ci];
            const pdt_cost_kind_t tkind = (v->kind == PDT_COST_COMBINED)
                                              ? (pdt_cost_kind_t)v->time_kind
                                              : (pdt_cost_kind_t)v->kind;
            pdt_cost_config_t cfg, cfg2;
            pdt_cost_t c, c2;
            base_config(s, &cfg);
            apply_config(v, &cfg);
            init_ok(&c, &cfg, s->n);
            for (size_t i = 0; i < s->nshape; i++) {
                const cpv_result_t *w = &s->result[i * CPV_NCFG + ci];
                const bool bounded = (w->gain_min != 0.0 || w->gain_max != 0.0);
                pdt_model_t shape = model_of(s, i, 1.0);
                pdt_model_t m;
                pdt_cost_profile_t r;
                pdt_real_t e;
                assert_int_equal(pdt_cost_profile(&c, &shape, (pdt_real_t)w->gain_min,
                                                  (pdt_real_t)w->gain_max, g_scratch, &r),
                                 PDT_OK);
                /* The cost of the model rebuilt with the returned gain. With
                 * estimate_offset the time part is already offset-free, and
                 * without it the offset is 0, so y0 need not move here. */
                m = with_gain(shape, r.gain);
                assert_int_equal(pdt_cost_eval(&c, &m, &e), PDT_OK);
                worst_rebuilt = fmax(worst_rebuilt, rel_err((double)e, (double)r.cost));
                assert_close(e, r.cost, CPV_RTOL_REBUILT, 0.0);
                /* 1% either side (inside the bounds) costs no less. */
                for (int sgn = -1; sgn <= 1; sgn += 2) {
                    pdt_real_t g = r.gain * ((pdt_real_t)1.0 + (pdt_real_t)sgn * (pdt_real_t)0.01);
                    pdt_real_t e2;
                    if (bounded && ((double)g < w->gain_min || (double)g > w->gain_max)) {
                        continue;
                    }
                    m = with_gain(shape, g);
                    assert_int_equal(pdt_cost_eval(&c, &m, &e2), PDT_OK);
                    if (!((double)e2 >= (double)r.cost * (1.0 - CPV_RTOL_REBUILT))) {
                        fail_msg("%s shape %zu %s: gain %g costs %.9g, %g costs %.9g", s->name, i,
                                 v->name, (double)r.gain, (double)r.cost, (double)g, (double)e2);
                    }
                }
                /* The offset: scoring the time part without the offset fit
                 * at y0 + offset gives the profiled time cost. Not for the
                 * prediction of an integrating shape (A(1) = 0: no output
                 * offset can move it; the offset is reported as 0). */
                if (v->kind == PDT_COST_FREQUENCY || !v->estimate_offset) {
                    assert_true(r.offset == (pdt_real_t)0.0);
                    continue;
                }
                if (tkind == PDT_COST_PREDICTION && s->kind[i] == 2 &&
                    s->param[4u * i + 2u] == 0.0) {
                    assert_true(r.offset == (pdt_real_t)0.0);
                    continue;
                }
                cfg2 = cfg;
                cfg2.kind = tkind;
                cfg2.estimate_offset = false;
                cfg2.use_frequency = false;
                cfg2.y0 = cfg.y0 + r.offset;
                assert_int_equal(pdt_cost_init(&c2, &cfg2, g_u, g_y, s->n, g_work2, sizeof g_work2),
                                 PDT_OK);
                m = with_gain(shape, r.gain);
                assert_int_equal(pdt_cost_eval(&c2, &m, &e), PDT_OK);
                worst_offset = fmax(worst_offset, rel_err((double)e, (double)r.ct));
                assert_close(e, r.ct, CPV_RTOL_REBUILT, 0.0);
            }
        }
    }
    print_message("worst relative error, profile cost vs rebuilt model: %.3g; "
                  "time cost at y0 + offset vs ct: %.3g\n",
                  worst_rebuilt, worst_offset);
}

/* Bounds that exclude the optimum put the gain on the nearer bound; a
 * bound pair lo = hi pins it. */
static void test_profile_bounds(void **state)
{
    const cpv_set_t *s = &cpv_sets[0];
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    pdt_model_t m = model_of(s, 0, 1.0);
    pdt_cost_profile_t r, rb;
    (void)state;
    load_set(s);
    base_config(s, &cfg);
    cfg.kind = PDT_COST_SIMULATION;
    cfg.use_frequency = false;
    init_ok(&c, &cfg, s->n);
    assert_int_equal(pdt_cost_profile(&c, &m, (pdt_real_t)0.0, (pdt_real_t)0.0, g_scratch, &r),
                     PDT_OK);
    assert_true(r.gain > (pdt_real_t)1.5); /* the data's gain is 2 */
    assert_int_equal(pdt_cost_profile(&c, &m, (pdt_real_t)3.0, (pdt_real_t)4.0, g_scratch, &rb),
                     PDT_OK);
    assert_true(rb.gain == (pdt_real_t)3.0 && rb.cost > r.cost);
    assert_int_equal(pdt_cost_profile(&c, &m, (pdt_real_t)-4.0, (pdt_real_t)1.0, g_scratch, &rb),
                     PDT_OK);
    assert_true(rb.gain == (pdt_real_t)1.0);
    assert_int_equal(pdt_cost_profile(&c, &m, (pdt_real_t)1.25, (pdt_real_t)1.25, g_scratch, &rb),
                     PDT_OK);
    assert_true(rb.gain == (pdt_real_t)1.25);
    /* A range holding the optimum changes nothing. */
    assert_int_equal(pdt_cost_profile(&c, &m, (pdt_real_t)-10.0, (pdt_real_t)10.0, g_scratch, &rb),
                     PDT_OK);
    assert_true(rb.gain == r.gain && rb.cost == r.cost && rb.offset == r.offset);
}

/* A zero weight drops its part from COMBINED: phi_f = 0 profiles as the
 * time kind alone, phi_t = 0 as FREQUENCY (the dropped part reads 0). */
static void test_profile_zero_weights(void **state)
{
    const cpv_set_t *s = &cpv_sets[3];
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    (void)state;
    load_set(s);
    for (size_t i = 0; i < s->nshape; i++) {
        pdt_model_t m = model_of(s, i, 1.0);
        pdt_cost_profile_t rc, rs;
        for (int tk = 0; tk < 2; tk++) {
            base_config(s, &cfg);
            cfg.time_kind = (pdt_cost_kind_t)tk;
            cfg.kind = PDT_COST_COMBINED;
            cfg.phi_t = (pdt_real_t)2.0;
            cfg.phi_f = (pdt_real_t)0.0;
            init_ok(&c, &cfg, s->n);
            assert_int_equal(
                pdt_cost_profile(&c, &m, (pdt_real_t)0.0, (pdt_real_t)0.0, g_scratch, &rc), PDT_OK);
            cfg.kind = (pdt_cost_kind_t)tk;
            init_ok(&c, &cfg, s->n);
            assert_int_equal(
                pdt_cost_profile(&c, &m, (pdt_real_t)0.0, (pdt_real_t)0.0, g_scratch, &rs), PDT_OK);
            assert_close(rc.gain, rs.gain, CPV_RTOL, 0.0);
            assert_close(rc.offset, rs.offset, CPV_RTOL, CPV_RTOL);
            assert_close(rc.ct, rs.ct, CPV_RTOL, 0.0);
            assert_close(rc.cost, 2.0 * (double)rs.cost, CPV_RTOL, 0.0);
            assert_true(rc.cf == (pdt_real_t)0.0);
        }
        base_config(s, &cfg);
        cfg.kind = PDT_COST_COMBINED;
        cfg.phi_t = (pdt_real_t)0.0;
        cfg.phi_f = (pdt_real_t)0.5;
        init_ok(&c, &cfg, s->n);
        assert_int_equal(pdt_cost_profile(&c, &m, (pdt_real_t)0.0, (pdt_real_t)0.0, g_scratch, &rc),
                         PDT_OK);
        cfg.kind = PDT_COST_FREQUENCY;
        init_ok(&c, &cfg, s->n);
        assert_int_equal(pdt_cost_profile(&c, &m, (pdt_real_t)0.0, (pdt_real_t)0.0, g_scratch, &rs),
                         PDT_OK);
        assert_close(rc.gain, rs.gain, CPV_RTOL, 0.0);
        assert_close(rc.cf, rs.cf, CPV_RTOL, 0.0);
        assert_close(rc.cost, 0.5 * (double)rs.cost, CPV_RTOL, 0.0);
        assert_true(rc.ct == (pdt_real_t)0.0 && rc.offset == (pdt_real_t)0.0);
    }
}

/* pdt_cost_simulate is pdt_discrete_simulate on the deviation input, plus y0. */
static void test_simulate_matches_dmodel(void **state)
{
    (void)state;
    for (size_t si = 0; si < CPV_NSETS; si++) {
        const cpv_set_t *s = &cpv_sets[si];
        pdt_cost_config_t cfg;
        pdt_cost_t c;
        load_set(s);
        base_config(s, &cfg);
        cfg.use_frequency = false;
        init_ok(&c, &cfg, s->n);
        for (size_t k = 0; k < s->n; k++) {
            g_dev[k] = g_u[k] - cfg.u0;
        }
        for (size_t i = 0; i < s->nshape; i++) {
            pdt_discrete_t d = dmodel_of(s->kind[i], s->delay_frac[i], s->coef_frac + 7u * i);
            pdt_real_t ys = (pdt_real_t)y_scale(s);
            assert_int_equal(pdt_discrete_simulate(&d, g_dev, s->n, g_ref), PDT_OK);
            assert_int_equal(pdt_cost_simulate(&c, &d, g_ysim), PDT_OK);
            for (size_t k = 0; k < s->n; k++) {
                /* Same recursion; only the rounding of adding y0 differs. */
                assert_close(g_ysim[k], g_ref[k] + cfg.y0, 0.0,
                             (PDT_REAL_DOUBLE ? 1e-12 : 1e-5) * ((double)ys + fabs(s->y0)));
            }
        }
    }
}

/* whole_record scores n - order samples, so only delay_max >= n and
 * n - 2 < PDT_MIN_SAMPLES are too short; the paper's window needs
 * n - delay_max - 2 >= PDT_MIN_SAMPLES. */
static void test_whole_record_too_short(void **state)
{
    const cpv_set_t *s = &cpv_sets[0];
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    const size_t n = s->n;
    (void)state;
    load_set(s);
    base_config(s, &cfg);
    cfg.use_frequency = false;
    cfg.delay_max = n - 2u - PDT_MIN_SAMPLES;
    cfg.whole_record = false;
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, n, g_work, sizeof g_work), PDT_OK);
    cfg.delay_max++;
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, n, g_work, sizeof g_work),
                     PDT_ERR_TOO_SHORT);
    cfg.whole_record = true;
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, n, g_work, sizeof g_work), PDT_OK);
    cfg.delay_max = n - 1u;
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, n, g_work, sizeof g_work), PDT_OK);
    cfg.delay_max = n;
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, n, g_work, sizeof g_work),
                     PDT_ERR_TOO_SHORT);
    /* The shortest records. */
    cfg.delay_max = PDT_MIN_SAMPLES + 1u;
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, PDT_MIN_SAMPLES + 2u, g_work, sizeof g_work),
                     PDT_OK);
    assert_int_equal(c.cfg.delay_max, PDT_MIN_SAMPLES + 1u);
    cfg.delay_max = 0;
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, PDT_MIN_SAMPLES + 1u, g_work, sizeof g_work),
                     PDT_ERR_TOO_SHORT);
    cfg.whole_record = false;
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, PDT_MIN_SAMPLES + 2u, g_work, sizeof g_work),
                     PDT_OK);
    cfg.delay_max = 1;
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, PDT_MIN_SAMPLES + 2u, g_work, sizeof g_work),
                     PDT_ERR_TOO_SHORT);
    /* With spectra the rule is the same. */
    cfg.use_frequency = true;
    cfg.whole_record = true;
    cfg.delay_max = n - 1u;
    init_ok(&c, &cfg, n);
    /* The whole record is scored even with the largest delay bound: a
     * model at delay n - 1 sees none of its input, so its simulation cost
     * without the offset fit is the mean square of y - y0 over k = 0 ..
     * n-1. */
    {
        pdt_discrete_t d = dmodel_of(s->kind[0], 0, s->coef_frac);
        pdt_real_t v;
        double want = 0.0;
        cfg.use_frequency = false;
        cfg.estimate_offset = false;
        init_ok(&c, &cfg, n);
        d.delay = n - 1u;
        assert_int_equal(pdt_cost_simulation(&c, &d, &v), PDT_OK);
        for (size_t k = 0; k < n; k++) {
            double e = (double)g_y[k] - s->y0;
            want += e * e;
        }
        assert_close(v, want / (double)n, CPV_RTOL, 0.0);
    }
}

/* ---- bad inputs ---- */

static void fill_pattern(void *p, size_t n)
{
    memset(p, 0xA5, n);
}

static void assert_pattern(const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    for (size_t i = 0; i < n; i++) {
        if (b[i] != 0xA5u) {
            fail_msg("byte %zu of an output changed on error", i);
        }
    }
}

/* Expects pdt_cost_profile to fail with want, leaving *out and the scratch
 * untouched. */
static void profile_fails(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t lo, pdt_real_t hi,
                          pdt_status_t want, int line)
{
    pdt_cost_profile_t out;
    pdt_status_t got;
    fill_pattern(&out, sizeof out);
    canary_fill(g_scratch, CPV_NMAX + CANARY_COUNT);
    got = pdt_cost_profile(c, m, lo, hi, g_scratch, &out);
    if (got != want) {
        fail_msg("line %d: status %d, want %d", line, (int)got, (int)want);
    }
    assert_pattern(&out, sizeof out);
    canary_check(g_scratch, CPV_NMAX + CANARY_COUNT);
}

#define PROFILE_FAILS(c, m, lo, hi, want)                                                          \
    profile_fails((c), (m), (pdt_real_t)(lo), (pdt_real_t)(hi), (want), __LINE__)

static void test_profile_errors(void **state)
{
    const cpv_set_t *s = &cpv_sets[0];
    pdt_cost_config_t cfg;
    pdt_cost_t c, cnof, zero;
    pdt_model_t m0 = model_of(s, 0, 1.0);
    pdt_model_t m;
    pdt_cost_profile_t out;
    (void)state;
    load_set(s);
    base_config(s, &cfg);
    cfg.delay_min = 3;
    init_ok(&c, &cfg, s->n); /* COMBINED */
    memset(&zero, 0, sizeof zero);

    /* NULL and unprepared */
    PROFILE_FAILS(NULL, &m0, 0, 0, PDT_ERR_ARG);
    PROFILE_FAILS(&zero, &m0, 0, 0, PDT_ERR_ARG);
    PROFILE_FAILS(&c, NULL, 0, 0, PDT_ERR_ARG);
    fill_pattern(&out, sizeof out);
    assert_int_equal(pdt_cost_profile(&c, &m0, (pdt_real_t)0.0, (pdt_real_t)0.0, NULL, &out),
                     PDT_ERR_ARG);
    assert_pattern(&out, sizeof out);
    assert_int_equal(pdt_cost_profile(&c, &m0, (pdt_real_t)0.0, (pdt_real_t)0.0, g_scratch, NULL),
                     PDT_ERR_ARG);

    /* bounds */
    PROFILE_FAILS(&c, &m0, 2.0, 1.0, PDT_ERR_BOUNDS);
    PROFILE_FAILS(&c, &m0, 0.0, -1e-3, PDT_ERR_BOUNDS);
    PROFILE_FAILS(&c, &m0, NAN, 1.0, PDT_ERR_ARG);
    PROFILE_FAILS(&c, &m0, 0.0, NAN, PDT_ERR_ARG);
    PROFILE_FAILS(&c, &m0, -INFINITY, 1.0, PDT_ERR_ARG);
    PROFILE_FAILS(&c, &m0, 0.0, INFINITY, PDT_ERR_ARG);
    PROFILE_FAILS(&c, &m0, INFINITY, -INFINITY, PDT_ERR_ARG); /* ARG before BOUNDS */

    /* invalid shapes */
    m = m0;
    m.p.fopdt.tau = (pdt_real_t)0.0;
    PROFILE_FAILS(&c, &m, 0, 0, PDT_ERR_ARG);
    m = m0;
    m.p.fopdt.K = (pdt_real_t)NAN;
    PROFILE_FAILS(&c, &m, 0, 0, PDT_ERR_ARG);
    m = m0;
    m.p.fopdt.Td = (pdt_real_t)-0.1;
    PROFILE_FAILS(&c, &m, 0, 0, PDT_ERR_ARG);
    m = m0;
    m.kind = (pdt_model_kind_t)3;
    PROFILE_FAILS(&c, &m, 0, 0, PDT_ERR_ARG);
    m = model_of(s, 2, 1.0); /* SOPDT */
    assert_int_equal(m.kind, PDT_MODEL_SOPDT);
    m.p.sopdt.a = (pdt_real_t)0.0;
    PROFILE_FAILS(&c, &m, 0, 0, PDT_ERR_ARG);
    m = model_of(s, 2, 1.0);
    m.p.sopdt.b = (pdt_real_t)INFINITY;
    PROFILE_FAILS(&c, &m, 0, 0, PDT_ERR_ARG);

    /* delay outside [delay_min, delay_max] (fractional: floor(Td / Ts)) */
    m = m0;
    m.p.fopdt.Td = (pdt_real_t)(((double)s->delay_max + 1.2) * s->Ts);
    PROFILE_FAILS(&c, &m, 0, 0, PDT_ERR_ARG);
    m.p.fopdt.Td = (pdt_real_t)(2.7 * s->Ts); /* floor 2 < delay_min 3 */
    PROFILE_FAILS(&c, &m, 0, 0, PDT_ERR_ARG);
    m.p.fopdt.Td = (pdt_real_t)1e30;
    PROFILE_FAILS(&c, &m, 0, 0, PDT_ERR_ARG);
    m.p.fopdt.Td = (pdt_real_t)(3.2 * s->Ts);
    assert_int_equal(pdt_cost_profile(&c, &m, (pdt_real_t)0.0, (pdt_real_t)0.0, g_scratch, &out),
                     PDT_OK);
    /* integer mode: round(Td / Ts) */
    cfg.delay_mode = PDT_DELAY_INTEGER;
    init_ok(&c, &cfg, s->n);
    m.p.fopdt.Td = (pdt_real_t)(((double)s->delay_max + 0.7) * s->Ts);
    PROFILE_FAILS(&c, &m, 0, 0, PDT_ERR_ARG);
    m.p.fopdt.Td = (pdt_real_t)(2.4 * s->Ts);
    PROFILE_FAILS(&c, &m, 0, 0, PDT_ERR_ARG);
    m.p.fopdt.Td = (pdt_real_t)(2.6 * s->Ts);
    assert_int_equal(pdt_cost_profile(&c, &m, (pdt_real_t)0.0, (pdt_real_t)0.0, g_scratch, &out),
                     PDT_OK);
    /* FREQUENCY ignores the dead time. */
    cfg.kind = PDT_COST_FREQUENCY;
    init_ok(&c, &cfg, s->n);
    m.p.fopdt.Td = (pdt_real_t)1e30;
    assert_int_equal(pdt_cost_profile(&c, &m, (pdt_real_t)0.0, (pdt_real_t)0.0, g_scratch, &out),
                     PDT_OK);
    assert_true(out.ct == (pdt_real_t)0.0 && out.offset == (pdt_real_t)0.0);

    /* FREQUENCY and COMBINED need spectra; the time kinds do not. */
    cfg.use_frequency = false;
    cfg.delay_mode = PDT_DELAY_FRACTIONAL;
    for (int k = 0; k < 4; k++) {
        cfg.kind = (pdt_cost_kind_t)k;
        assert_int_equal(pdt_cost_init(&cnof, &cfg, g_u, g_y, s->n, g_work, sizeof g_work), PDT_OK);
        if (k == PDT_COST_FREQUENCY || k == PDT_COST_COMBINED) {
            PROFILE_FAILS(&cnof, &m0, 0, 0, PDT_ERR_ARG);
        } else {
            assert_int_equal(
                pdt_cost_profile(&cnof, &m0, (pdt_real_t)0.0, (pdt_real_t)0.0, g_scratch, &out),
                PDT_OK);
            assert_true(out.cf == (pdt_real_t)0.0 && out.cost == out.ct);
        }
    }
}

/* The header lists a delay outside the bounds as PDT_ERR_ARG for the
 * profile, and pdt_cost_eval checks it for COMBINED whatever phi_t: so
 * must the profile when phi_t = 0. */
static void test_profile_delay_check_phi_t_zero(void **state)
{
    const cpv_set_t *s = &cpv_sets[0];
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    pdt_model_t m = model_of(s, 0, 1.0);
    pdt_real_t v = (pdt_real_t)123.0;
    (void)state;
    load_set(s);
    base_config(s, &cfg);
    cfg.phi_t = (pdt_real_t)0.0;
    init_ok(&c, &cfg, s->n);
    m.p.fopdt.Td = (pdt_real_t)(((double)s->delay_max + 1.2) * s->Ts);
    assert_int_equal(pdt_cost_eval(&c, &m, &v), PDT_ERR_ARG);
    PROFILE_FAILS(&c, &m, 0, 0, PDT_ERR_ARG);
}

static void test_simulate_errors(void **state)
{
    const cpv_set_t *s = &cpv_sets[0];
    pdt_cost_config_t cfg;
    pdt_cost_t c, zero;
    pdt_discrete_t d0 = dmodel_of(s->kind[0], s->delay_frac[0], s->coef_frac);
    pdt_discrete_t d;
    (void)state;
    load_set(s);
    base_config(s, &cfg);
    cfg.use_frequency = false;
    init_ok(&c, &cfg, s->n);
    memset(&zero, 0, sizeof zero);
    canary_fill(g_ysim, CPV_NMAX + CANARY_COUNT);
    assert_int_equal(pdt_cost_simulate(NULL, &d0, g_ysim), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_simulate(&zero, &d0, g_ysim), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_simulate(&c, NULL, g_ysim), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_simulate(&c, &d0, NULL), PDT_ERR_ARG);
    for (int i = 0; i < 8; i++) {
        d = d0;
        switch (i) {
        case 0:
            d.order = 0;
            break;
        case 1:
            d.order = 3;
            break;
        case 2:
            d.b[0] = (pdt_real_t)NAN;
            break;
        case 3:
            d.b[1] = (pdt_real_t)INFINITY;
            break;
        case 4:
            d.b[2] = (pdt_real_t)-INFINITY;
            break;
        case 5:
            d.d[0] = (pdt_real_t)NAN;
            break;
        case 6:
            d.order = 2;
            d.d[1] = (pdt_real_t)NAN;
            break;
        default:
            d.order = 255;
            break;
        }
        assert_int_equal(pdt_cost_simulate(&c, &d, g_ysim), PDT_ERR_ARG);
    }
    canary_check(g_ysim, CPV_NMAX + CANARY_COUNT);
    /* Unused coefficients do not matter: d[1] of a first-order model and
     * a[] (the delta form d[] is what runs). Any delay is allowed. */
    d = d0;
    d.d[1] = (pdt_real_t)NAN;
    d.a[0] = (pdt_real_t)NAN;
    d.a[1] = (pdt_real_t)INFINITY;
    d.delay = s->n + 5u;
    canary_fill(g_ysim + s->n, CANARY_COUNT);
    assert_int_equal(pdt_cost_simulate(&c, &d, g_ysim), PDT_OK);
    canary_check(g_ysim + s->n, CANARY_COUNT);
    for (size_t k = 0; k < s->n; k++) {
        assert_true(g_ysim[k] == (pdt_real_t)s->y0);
    }
    /* The largest delays, where delay + 1 would wrap around to 0 in the
     * input index: still no input reaches the record. */
    for (size_t back = 1; back <= 3; back++) {
        d.delay = (size_t)0 - back;
        assert_int_equal(pdt_cost_simulate(&c, &d, g_ysim), PDT_OK);
        for (size_t k = 0; k < s->n; k++) {
            assert_true(g_ysim[k] == (pdt_real_t)s->y0);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vectors_whole_record),
        cmocka_unit_test(test_vectors_profile),
        cmocka_unit_test(test_vectors_many_and_hints),
        cmocka_unit_test(test_many_errors),
        cmocka_unit_test(test_shift_profiles),
        cmocka_unit_test(test_shift_errors),
        cmocka_unit_test(test_accuracy_scales),
        cmocka_unit_test(test_vectors_simulate),
        cmocka_unit_test(test_profile_properties),
        cmocka_unit_test(test_profile_bounds),
        cmocka_unit_test(test_profile_zero_weights),
        cmocka_unit_test(test_simulate_matches_dmodel),
        cmocka_unit_test(test_whole_record_too_short),
        cmocka_unit_test(test_profile_errors),
        cmocka_unit_test(test_profile_delay_check_phi_t_zero),
        cmocka_unit_test(test_simulate_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
