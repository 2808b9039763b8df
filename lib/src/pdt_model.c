/*
 * pdtfit models: checks, form conversions, step and frequency responses.
 *
 * The SOPDT step response is evaluated from closed forms arranged so that no
 * term cancels badly at small times, where discretisation needs it most
 * (Ts/tau of 0.01 is the normal case): see pdt_model_sopdt_unit_step().
 */
#include "pdt/pdt_model.h"

#include "pdt_internal.h"
#include "pdt_model_priv.h"

/* ---- validity checks ---------------------------------------------------- */

static bool fopdt_valid(const pdt_model_fopdt_t *p)
{
    return pdt_finite(p->K) && pdt_finite(p->tau) && pdt_finite(p->Td) && p->tau > PDT_R(0.0) &&
           p->Td >= PDT_R(0.0);
}

static bool sopdt_valid(const pdt_model_sopdt_t *p)
{
    return pdt_finite(p->k) && pdt_finite(p->a) && pdt_finite(p->b) && pdt_finite(p->Td) &&
           p->a > PDT_R(0.0) && p->b >= PDT_R(0.0) && p->Td >= PDT_R(0.0);
}

pdt_status_t pdt_model_check(const pdt_model_t *m)
{
    if (m == NULL) {
        return PDT_ERR_ARG;
    }
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        return fopdt_valid(&m->p.fopdt) ? PDT_OK : PDT_ERR_ARG;
    case PDT_MODEL_SOPDT:
        return sopdt_valid(&m->p.sopdt) ? PDT_OK : PDT_ERR_ARG;
    }
    return PDT_ERR_ARG; /* not a kind */
}

pdt_real_t pdt_model_dead_time(const pdt_model_t *m)
{
    if (m == NULL) {
        return PDT_R(0.0);
    }
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        return m->p.fopdt.Td;
    case PDT_MODEL_SOPDT:
        return m->p.sopdt.Td;
    }
    return PDT_R(0.0);
}

/* ---- conversions -------------------------------------------------------- */

pdt_status_t pdt_model_sopdt_from_natural(const pdt_model_natural_t *in, pdt_model_sopdt_t *out)
{
    if (in == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    if (!(pdt_finite(in->K) && pdt_finite(in->wn) && pdt_finite(in->zeta) && pdt_finite(in->Td) &&
          in->wn > PDT_R(0.0) && in->zeta > PDT_R(0.0) && in->Td >= PDT_R(0.0))) {
        return PDT_ERR_ARG;
    }
    pdt_model_sopdt_t r;
    r.b = in->wn * in->wn;
    r.a = PDT_R(2.0) * in->zeta * in->wn;
    r.k = in->K * r.b;
    r.Td = in->Td;
    if (!sopdt_valid(&r) || r.b <= PDT_R(0.0)) {
        return PDT_ERR_ARG; /* over- or underflow of the products */
    }
    *out = r;
    return PDT_OK;
}

pdt_status_t pdt_model_sopdt_to_natural(const pdt_model_sopdt_t *in, pdt_model_natural_t *out)
{
    if (in == NULL || out == NULL || !sopdt_valid(in)) {
        return PDT_ERR_ARG;
    }
    if (in->b == PDT_R(0.0)) {
        return PDT_ERR_NO_FORM;
    }
    pdt_model_natural_t r;
    r.wn = pdt_sqrt(in->b);
    r.zeta = in->a / (PDT_R(2.0) * r.wn);
    r.K = in->k / in->b;
    r.Td = in->Td;
    if (!(pdt_finite(r.K) && pdt_finite(r.zeta))) {
        return PDT_ERR_NO_FORM; /* b so small that the gain overflows */
    }
    *out = r;
    return PDT_OK;
}

pdt_status_t pdt_model_sopdt_from_tc(const pdt_model_tc_t *in, pdt_model_sopdt_t *out)
{
    if (in == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    if (!(pdt_finite(in->K) && pdt_finite(in->T1) && pdt_finite(in->T2) && pdt_finite(in->Td) &&
          in->T1 > PDT_R(0.0) && in->T2 > PDT_R(0.0) && in->Td >= PDT_R(0.0))) {
        return PDT_ERR_ARG;
    }
    pdt_model_sopdt_t r;
    if (in->complex) {
        /* (re^2 + im^2) s^2 + 2 re s + 1, scaled to a monic s^2 */
        pdt_real_t p = in->T1 * in->T1 + in->T2 * in->T2;
        r.b = PDT_R(1.0) / p;
        r.a = PDT_R(2.0) * in->T1 * r.b;
    } else {
        r.b = PDT_R(1.0) / (in->T1 * in->T2);
        r.a = PDT_R(1.0) / in->T1 + PDT_R(1.0) / in->T2;
    }
    r.k = in->K * r.b;
    r.Td = in->Td;
    if (!sopdt_valid(&r) || r.b <= PDT_R(0.0)) {
        return PDT_ERR_ARG;
    }
    *out = r;
    return PDT_OK;
}

pdt_status_t pdt_model_sopdt_to_tc(const pdt_model_sopdt_t *in, pdt_model_tc_t *out)
{
    if (in == NULL || out == NULL || !sopdt_valid(in)) {
        return PDT_ERR_ARG;
    }
    if (in->b == PDT_R(0.0)) {
        return PDT_ERR_NO_FORM;
    }
    pdt_model_tc_t r;
    pdt_real_t sigma = PDT_R(0.5) * in->a;
    pdt_real_t d = sigma * sigma - in->b;
    if (d >= PDT_R(0.0)) {
        /* Poles -(sigma +/- sqrt(d)); the slow one from the product of the
         * poles (= b) so that it does not cancel. */
        pdt_real_t fast = sigma + pdt_sqrt(d);
        r.T1 = fast / in->b;
        r.T2 = PDT_R(1.0) / fast;
        r.complex = false;
    } else {
        r.T1 = sigma / in->b;
        r.T2 = pdt_sqrt(-d) / in->b;
        r.complex = true;
    }
    r.K = in->k / in->b;
    r.Td = in->Td;
    if (!(pdt_finite(r.K) && pdt_finite(r.T1) && r.T2 > PDT_R(0.0))) {
        return PDT_ERR_NO_FORM;
    }
    *out = r;
    return PDT_OK;
}

pdt_status_t pdt_model_sopdt_from_integ(const pdt_model_integ_t *in, pdt_model_sopdt_t *out)
{
    if (in == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    if (!(pdt_finite(in->Ki) && pdt_finite(in->T) && pdt_finite(in->Td) && in->T > PDT_R(0.0) &&
          in->Td >= PDT_R(0.0))) {
        return PDT_ERR_ARG;
    }
    pdt_model_sopdt_t r;
    r.a = PDT_R(1.0) / in->T;
    r.k = in->Ki / in->T;
    r.b = PDT_R(0.0);
    r.Td = in->Td;
    if (!sopdt_valid(&r)) {
        return PDT_ERR_ARG;
    }
    *out = r;
    return PDT_OK;
}

pdt_status_t pdt_model_sopdt_to_integ(const pdt_model_sopdt_t *in, pdt_model_integ_t *out)
{
    if (in == NULL || out == NULL || !sopdt_valid(in)) {
        return PDT_ERR_ARG;
    }
    if (in->b != PDT_R(0.0)) {
        return PDT_ERR_NO_FORM;
    }
    pdt_model_integ_t r;
    r.Ki = in->k / in->a;
    r.T = PDT_R(1.0) / in->a;
    r.Td = in->Td;
    if (!(pdt_finite(r.Ki) && pdt_finite(r.T))) {
        return PDT_ERR_NO_FORM;
    }
    *out = r;
    return PDT_OK;
}

pdt_status_t pdt_model_dc_gain(const pdt_model_t *m, pdt_real_t *gain)
{
    if (gain == NULL || pdt_model_check(m) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        *gain = m->p.fopdt.K;
        return PDT_OK;
    case PDT_MODEL_SOPDT:
        if (m->p.sopdt.b == PDT_R(0.0)) {
            return PDT_ERR_NO_FORM;
        }
        *gain = m->p.sopdt.k / m->p.sopdt.b;
        return PDT_OK;
    }
    return PDT_ERR_ARG;
}

/* ---- step response ------------------------------------------------------ */

/* Series coefficients, highest order first for Horner's rule. Enough terms
 * for double precision on |x| <= 1. The float build starts further down
 * each table: the terms it skips are below a tenth of an ulp there, and
 * each is a multiply and an add in one chain that every SOPDT
 * discretisation (three step samples per evaluation) waits on. */
#if PDT_REAL_DOUBLE
#define PSI_TERMS  18u
#define P1_TERMS   19u
#define SINC_TERMS 9u
#else
#define PSI_TERMS  10u /* dropped: x^11 / 12! = 2e-9 */
#define P1_TERMS   11u /* dropped: 12 x^13 / 13! = 2e-9 */
#define SINC_TERMS 5u  /* dropped: u^6 / 13! = 2e-10 */
#endif

/* psi(x) = 1 - (1 - e^-x)/x = sum_{n>=1} (-1)^(n+1) x^n / (n+1)!:
 * c[j] = (-1)^(n+1)/(n+1)! for n = 18 - j. */
static const pdt_real_t psi_c[18] = {
    PDT_R(-8.22063524662433e-18),   PDT_R(1.5619206968586225e-16),  PDT_R(-2.8114572543455206e-15),
    PDT_R(4.779477332387385e-14),   PDT_R(-7.647163731819816e-13),  PDT_R(1.1470745597729725e-11),
    PDT_R(-1.6059043836821613e-10), PDT_R(2.08767569878681e-09),    PDT_R(-2.505210838544172e-08),
    PDT_R(2.755731922398589e-07),   PDT_R(-2.7557319223985893e-06), PDT_R(2.48015873015873e-05),
    PDT_R(-0.0001984126984126984),  PDT_R(0.001388888888888889),    PDT_R(-0.008333333333333333),
    PDT_R(0.041666666666666664),    PDT_R(-0.16666666666666666),    PDT_R(0.5)};

/* p1(x) = 1 - e^-x (1 + x) = sum_{n>=2} (-1)^n (n-1) x^n / n!:
 * c[j] for n = 20 - j. */
static const pdt_real_t p1_c[19] = {PDT_R(7.809603484293113e-18),
                                    PDT_R(-1.4797143443923793e-16),
                                    PDT_R(2.6552651846596585e-15),
                                    PDT_R(-4.498331606952833e-14),
                                    PDT_R(7.169215998581078e-13),
                                    PDT_R(-1.0706029224547743e-11),
                                    PDT_R(1.4911969277048643e-10),
                                    PDT_R(-1.9270852604185937e-09),
                                    PDT_R(2.296443268665491e-08),
                                    PDT_R(-2.505210838544172e-07),
                                    PDT_R(2.48015873015873e-06),
                                    PDT_R(-2.2045855379188714e-05),
                                    PDT_R(0.00017361111111111112),
                                    PDT_R(-0.0011904761904761906),
                                    PDT_R(0.006944444444444444),
                                    PDT_R(-0.03333333333333333),
                                    PDT_R(0.125),
                                    PDT_R(-0.3333333333333333),
                                    PDT_R(0.5)};

/* 1/(2n+1)! for n = 9..1, for 1 - sinh(z)/z and 1 - sin(z)/z. */
static const pdt_real_t sinc_c[9] = {
    PDT_R(8.22063524662433e-18),   PDT_R(2.8114572543455206e-15), PDT_R(7.647163731819816e-13),
    PDT_R(1.6059043836821613e-10), PDT_R(2.505210838544172e-08),  PDT_R(2.7557319223985893e-06),
    PDT_R(0.0001984126984126984),  PDT_R(0.008333333333333333),   PDT_R(0.16666666666666666)};

static pdt_real_t horner(const pdt_real_t *c, size_t n, pdt_real_t x)
{
    pdt_real_t s = PDT_R(0.0);
    for (size_t i = 0; i < n; i++) {
        s = s * x + c[i];
    }
    return s;
}

/* psi(x) = 1 - (1 - e^-x)/x for x >= 0; small x by its series. */
static pdt_real_t psi(pdt_real_t x)
{
    if (x < PDT_R(1.0)) {
        return x * horner(psi_c + (18u - PSI_TERMS), PSI_TERMS, x);
    }
    return (x + pdt_expm1(-x)) / x;
}

/* phi(x) = (1 - e^-x)/x for x > 0. */
static pdt_real_t phi(pdt_real_t x)
{
    return -pdt_expm1(-x) / x;
}

/* 1 - e^-x (1 + x) for x >= 0. */
static pdt_real_t one_minus_exp_lin(pdt_real_t x)
{
    if (x < PDT_R(1.0)) {
        return x * x * horner(p1_c + (19u - P1_TERMS), P1_TERMS, x);
    }
    return -pdt_expm1(-x) - x * pdt_exp(-x);
}

/* 1 - S/t where S = sinh(sqrt(u) t)/sqrt(u) (u = d t^2 > 0) or
 * sin(sqrt(-u) t)/sqrt(-u) (u < 0); a function of u alone. */
static pdt_real_t one_minus_sinc(pdt_real_t u)
{
    if (pdt_fabs(u) < PDT_R(1.0)) {
        return -u * horner(sinc_c + (9u - SINC_TERMS), SINC_TERMS, u);
    }
    if (u > PDT_R(0.0)) {
        pdt_real_t z = pdt_sqrt(u);
        return PDT_R(1.0) - pdt_sinh(z) / z;
    }
    pdt_real_t z = pdt_sqrt(-u);
    return PDT_R(1.0) - pdt_sin(z) / z;
}

pdt_real_t pdt_model_sopdt_unit_step(pdt_real_t a, pdt_real_t b, pdt_real_t t)
{
    if (!(t > PDT_R(0.0))) {
        return PDT_R(0.0);
    }
    pdt_real_t sigma = PDT_R(0.5) * a;
    pdt_real_t d = sigma * sigma - b;
    if (PDT_R(9.0) * d >= sigma * sigma) {
        /* Well separated real poles l1 <= l2/2 (and the integrator, l1 = 0):
         * h = t (psi(l2 t) - psi(l1 t)) / (l2 - l1). The difference is taken
         * of psi while psi is small and of phi = 1 - psi otherwise, so it
         * never loses more than a factor l2/(l2 - l1) <= 2. */
        pdt_real_t r = pdt_sqrt(d);
        pdt_real_t l2 = sigma + r;
        pdt_real_t l1 = b / l2;
        pdt_real_t x1 = l1 * t;
        pdt_real_t x2 = l2 * t;
        pdt_real_t p1 = psi(x1);
        pdt_real_t diff;
        if (p1 < PDT_R(0.5)) {
            diff = psi(x2) - p1;
        } else {
            diff = phi(x1) - phi(x2);
        }
        return t * diff / (PDT_R(2.0) * r);
    }
    pdt_real_t x = sigma * t;
    if (d > PDT_R(0.0)) {
        pdt_real_t r = pdt_sqrt(d);
        pdt_real_t rt = r * t;
        if (rt > PDT_R(1.0)) {
            /* Combine the exponents so that cosh/sinh cannot overflow; here
             * sigma t > 3 and the bracket is well below 1. */
            pdt_real_t q = sigma / r;
            pdt_real_t e = PDT_R(0.5) * (pdt_exp(-(sigma - r) * t) * (PDT_R(1.0) + q) +
                                         pdt_exp(-(sigma + r) * t) * (PDT_R(1.0) - q));
            return (PDT_R(1.0) - e) / b;
        }
    }
    /* Close real or complex poles: b h / k = [1 - e^-x (1 + x)]
     * + e^-x (1 - C) + sigma e^-x (t - S), each term accurate on its own:
     * 1 - C by the half-angle form, t - S by its series. */
    pdt_real_t ex = pdt_exp(-x);
    pdt_real_t one_minus_c;
    if (d > PDT_R(0.0)) {
        pdt_real_t s = pdt_sinh(PDT_R(0.5) * pdt_sqrt(d) * t);
        one_minus_c = PDT_R(-2.0) * s * s;
    } else if (d < PDT_R(0.0)) {
        pdt_real_t s = pdt_sin(PDT_R(0.5) * pdt_sqrt(-d) * t);
        one_minus_c = PDT_R(2.0) * s * s;
    } else {
        one_minus_c = PDT_R(0.0);
    }
    pdt_real_t sum =
        one_minus_exp_lin(x) + ex * one_minus_c + sigma * ex * t * one_minus_sinc(d * t * t);
    return sum / b;
}

static pdt_real_t fopdt_step1(const pdt_model_fopdt_t *p, pdt_real_t t)
{
    pdt_real_t s = t - p->Td;
    if (!(s > PDT_R(0.0))) {
        return PDT_R(0.0);
    }
    return -p->K * pdt_expm1(-s / p->tau);
}

pdt_status_t pdt_model_step(const pdt_model_t *m, const pdt_real_t *t, size_t n, pdt_real_t *y)
{
    if (t == NULL || y == NULL || pdt_model_check(m) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    for (size_t i = 0; i < n; i++) {
        if (!pdt_finite(t[i])) {
            return PDT_ERR_NONFINITE;
        }
    }
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        for (size_t i = 0; i < n; i++) {
            y[i] = fopdt_step1(&m->p.fopdt, t[i]);
        }
        break;
    case PDT_MODEL_SOPDT: {
        const pdt_model_sopdt_t *p = &m->p.sopdt;
        for (size_t i = 0; i < n; i++) {
            y[i] = p->k * pdt_model_sopdt_unit_step(p->a, p->b, t[i] - p->Td);
        }
        break;
    }
    }
    return PDT_OK;
}

/* ---- frequency response ------------------------------------------------- */

pdt_status_t pdt_model_freq(const pdt_model_t *m, const pdt_real_t *w, size_t n, pdt_real_t *mag,
                            pdt_real_t *phase)
{
    if (w == NULL || pdt_model_check(m) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    bool negative = false;
    for (size_t i = 0; i < n; i++) {
        if (!pdt_finite(w[i])) {
            return PDT_ERR_NONFINITE;
        }
        negative = negative || w[i] < PDT_R(0.0);
    }
    if (negative) {
        return PDT_ERR_ARG;
    }
    const bool negative_gain = pdt_model_gain_numerator(m) < PDT_R(0.0);
    for (size_t i = 0; i < n; i++) {
        if (mag != NULL) {
            mag[i] = pdt_model_magnitude_at(m, w[i]);
        }
        if (phase != NULL) {
            phase[i] = pdt_model_shape_phase(m, w[i]) - (negative_gain ? PDT_PI : PDT_R(0.0));
        }
    }
    return PDT_OK;
}

static pdt_real_t sopdt_magnitude(const pdt_model_sopdt_t *p, pdt_real_t w)
{
    if (p->b == PDT_R(0.0)) {
        /* k / (jw (jw + a)) */
        pdt_real_t den = w * pdt_hypot(w, p->a);
        if (den > PDT_R(0.0) || p->k == PDT_R(0.0)) {
            return den > PDT_R(0.0) ? pdt_fabs(p->k) / den : PDT_R(0.0);
        }
        return (pdt_real_t)INFINITY;
    }
    return pdt_fabs(p->k) / pdt_hypot(p->b - w * w, p->a * w);
}

pdt_real_t pdt_model_magnitude_at(const pdt_model_t *m, pdt_real_t w)
{
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        return pdt_fabs(m->p.fopdt.K) / pdt_hypot(PDT_R(1.0), w * m->p.fopdt.tau);
    case PDT_MODEL_SOPDT:
        return sopdt_magnitude(&m->p.sopdt, w);
    }
    return PDT_R(0.0);
}

static pdt_real_t sopdt_phase(const pdt_model_sopdt_t *p, pdt_real_t w)
{
    if (p->b == PDT_R(0.0)) {
        /* the pole at 0 gives -pi/2, also at w = 0 */
        return -PDT_R(0.5) * PDT_PI - pdt_atan2(w, p->a) - w * p->Td;
    }
    return -pdt_atan2(p->a * w, p->b - w * w) - w * p->Td;
}

pdt_real_t pdt_model_shape_phase(const pdt_model_t *m, pdt_real_t w)
{
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        return -pdt_atan(w * m->p.fopdt.tau) - w * m->p.fopdt.Td;
    case PDT_MODEL_SOPDT:
        return sopdt_phase(&m->p.sopdt, w);
    }
    return PDT_R(0.0);
}

pdt_real_t pdt_model_phase_crossover(const pdt_model_t *m)
{
    const pdt_real_t Td = pdt_model_dead_time(m);
    if (!(Td > PDT_R(0.0))) {
        return PDT_R(0.0);
    }
    pdt_real_t lo = PDT_R(0.0), hi = PDT_PI / Td;
    for (uint32_t i = 0; i < 64u; i++) {
        const pdt_real_t mid = PDT_R(0.5) * (lo + hi);
        if (mid <= lo || mid >= hi) {
            break;
        }
        if (pdt_model_shape_phase(m, mid) <= -PDT_PI) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    return PDT_R(0.5) * (lo + hi);
}

pdt_real_t pdt_model_split_gain(const pdt_model_t *m, pdt_model_t *shape)
{
    pdt_real_t K = PDT_R(0.0);
    *shape = *m;
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        K = m->p.fopdt.K;
        shape->p.fopdt.K = PDT_R(1.0);
        break;
    case PDT_MODEL_SOPDT:
        K = m->p.sopdt.k;
        shape->p.sopdt.k = PDT_R(1.0);
        break;
    }
    return K;
}

/* ---- the model-kind layer ------------------------------------------------ */

pdt_model_param_t pdt_model_kind_param(pdt_model_kind_t kind, uint32_t i)
{
    static const pdt_model_param_t fopdt[3] = {PDT_MODEL_PARAM_K, PDT_MODEL_PARAM_TAU,
                                               PDT_MODEL_PARAM_TD};
    static const pdt_model_param_t sopdt[4] = {PDT_MODEL_PARAM_K, PDT_MODEL_PARAM_A,
                                               PDT_MODEL_PARAM_B, PDT_MODEL_PARAM_TD};
    switch (kind) {
    case PDT_MODEL_FOPDT:
        return i < 3u ? fopdt[i] : PDT_MODEL_PARAM_NONE;
    case PDT_MODEL_SOPDT:
        return i < 4u ? sopdt[i] : PDT_MODEL_PARAM_NONE;
    }
    return PDT_MODEL_PARAM_NONE;
}

uint32_t pdt_model_params_get(const pdt_model_t *m, pdt_real_t *p)
{
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        p[0] = m->p.fopdt.K;
        p[1] = m->p.fopdt.tau;
        p[2] = m->p.fopdt.Td;
        return 3u;
    case PDT_MODEL_SOPDT:
        p[0] = m->p.sopdt.k;
        p[1] = m->p.sopdt.a;
        p[2] = m->p.sopdt.b;
        p[3] = m->p.sopdt.Td;
        return 4u;
    }
    return 0u;
}

void pdt_model_params_set(pdt_model_t *m, const pdt_real_t *p)
{
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        m->p.fopdt.K = p[0];
        m->p.fopdt.tau = p[1];
        m->p.fopdt.Td = p[2];
        break;
    case PDT_MODEL_SOPDT:
        m->p.sopdt.k = p[0];
        m->p.sopdt.a = p[1];
        m->p.sopdt.b = p[2];
        m->p.sopdt.Td = p[3];
        break;
    }
}

pdt_real_t pdt_model_gain_numerator(const pdt_model_t *m)
{
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        return m->p.fopdt.K;
    case PDT_MODEL_SOPDT:
        return m->p.sopdt.k;
    }
    return PDT_R(0.0);
}

void pdt_model_add_dead_time(pdt_model_t *m, pdt_real_t dTd)
{
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        m->p.fopdt.Td += dTd;
        break;
    case PDT_MODEL_SOPDT:
        m->p.sopdt.Td += dTd;
        break;
    }
}

void pdt_model_scale_gain(pdt_model_t *m, pdt_real_t g)
{
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        m->p.fopdt.K *= g;
        break;
    case PDT_MODEL_SOPDT:
        m->p.sopdt.k *= g;
        break;
    }
}

bool pdt_model_integrates(const pdt_model_t *m)
{
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        return false;
    case PDT_MODEL_SOPDT:
        return !(m->p.sopdt.b > PDT_R(0.0));
    }
    return false;
}

void pdt_model_static_gain_ratio(const pdt_model_t *m, pdt_real_t *num, pdt_real_t *den)
{
    *num = PDT_R(1.0);
    *den = PDT_R(1.0);
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        break;
    case PDT_MODEL_SOPDT:
        *num = m->p.sopdt.b > PDT_R(0.0) ? m->p.sopdt.b : m->p.sopdt.a;
        *den = m->p.sopdt.k;
        break;
    }
}
