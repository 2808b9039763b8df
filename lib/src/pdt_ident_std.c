/*
 * The uncertainty of the printed parameters (pdt_ident_std_printed): the
 * covariance of the model's own parameters carried through the derivatives
 * of the printed ones (the delta method).
 */
#include "pdt/pdt_ident.h"
#include "pdt_internal.h"
#include "pdt_model_priv.h"

/* The model's own parameters: FOPDT K, tau, Td, y0; SOPDT k, a, b, Td, y0. */
#define NATIVE_MAX PDT_IDENT_MAX_PARAMS

/* The printed parameters' count as an unsigned loop bound. */
#define N_PAR ((uint32_t)PDT_IDENT_PAR_COUNT)

typedef pdt_real_t jacobian_t[PDT_IDENT_PAR_COUNT][NATIVE_MAX];

static void set_row(pdt_ident_printed_t *p, pdt_ident_par_t i)
{
    p->have |= (uint32_t)1u << (uint32_t)i;
}

static void lag_rows(pdt_ident_printed_t *p, jacobian_t J)
{
    set_row(p, PDT_IDENT_PAR_K);
    set_row(p, PDT_IDENT_PAR_TAU);
    set_row(p, PDT_IDENT_PAR_TD);
    J[PDT_IDENT_PAR_K][0] = PDT_R(1.0);
    J[PDT_IDENT_PAR_TAU][1] = PDT_R(1.0);
    J[PDT_IDENT_PAR_TD][2] = PDT_R(1.0);
    J[PDT_IDENT_PAR_Y0][3] = PDT_R(1.0);
}

/* tau1 (the slow pole's time constant) and tau2 of a real pair, as
 * pdt_model_sopdt_to_tc gives them, with their derivatives by a and b;
 * none at a double pole, where they have none. */
static void real_pair_rows(const pdt_model_view_t *s, pdt_ident_printed_t *p, jacobian_t J)
{
    const pdt_real_t sigma = PDT_R(0.5) * s->a;
    const pdt_real_t d = (sigma * sigma) - s->b;
    if (d < PDT_R(0.0)) {
        return;
    }
    const pdt_real_t q = pdt_sqrt(d);
    const pdt_real_t fast = sigma + q;
    set_row(p, PDT_IDENT_PAR_TAU1);
    set_row(p, PDT_IDENT_PAR_TAU2);
    if (q <= PDT_R(0.0)) {
        p->std[PDT_IDENT_PAR_TAU1] = (pdt_real_t)INFINITY;
        p->std[PDT_IDENT_PAR_TAU2] = (pdt_real_t)INFINITY;
        return;
    }
    const pdt_real_t dfa = PDT_R(0.5) * (PDT_R(1.0) + (sigma / q));
    const pdt_real_t dfb = PDT_R(-0.5) / q;
    J[PDT_IDENT_PAR_TAU1][1] = dfa / s->b;
    J[PDT_IDENT_PAR_TAU1][2] = (dfb / s->b) - (fast / (s->b * s->b));
    J[PDT_IDENT_PAR_TAU2][1] = -dfa / (fast * fast);
    J[PDT_IDENT_PAR_TAU2][2] = -dfb / (fast * fast);
}

static void pair_rows(const pdt_model_view_t *s, pdt_ident_printed_t *p, jacobian_t J)
{
    set_row(p, PDT_IDENT_PAR_TD);
    set_row(p, PDT_IDENT_PAR_A);
    set_row(p, PDT_IDENT_PAR_B);
    J[PDT_IDENT_PAR_TD][3] = PDT_R(1.0);
    J[PDT_IDENT_PAR_Y0][4] = PDT_R(1.0);
    J[PDT_IDENT_PAR_A][1] = PDT_R(1.0);
    J[PDT_IDENT_PAR_B][2] = PDT_R(1.0);
    if (s->b > PDT_R(0.0)) {
        const pdt_real_t wn = pdt_sqrt(s->b);
        set_row(p, PDT_IDENT_PAR_K);
        set_row(p, PDT_IDENT_PAR_WN);
        set_row(p, PDT_IDENT_PAR_ZETA);
        J[PDT_IDENT_PAR_K][0] = PDT_R(1.0) / s->b;
        J[PDT_IDENT_PAR_K][2] = -s->K / (s->b * s->b);
        J[PDT_IDENT_PAR_WN][2] = PDT_R(0.5) / wn;
        J[PDT_IDENT_PAR_ZETA][1] = PDT_R(0.5) / wn;
        J[PDT_IDENT_PAR_ZETA][2] = -s->a / (PDT_R(4.0) * s->b * wn);
        real_pair_rows(s, p, J);
    } else {
        /* The integrator k / (s (s + a)) = Ki / (s (T s + 1)), wn 0. */
        set_row(p, PDT_IDENT_PAR_KI);
        set_row(p, PDT_IDENT_PAR_WN);
        set_row(p, PDT_IDENT_PAR_TAU2);
        J[PDT_IDENT_PAR_KI][0] = PDT_R(1.0) / s->a;
        J[PDT_IDENT_PAR_KI][1] = -s->K / (s->a * s->a);
        J[PDT_IDENT_PAR_TAU2][1] = PDT_R(-1.0) / (s->a * s->a);
    }
}

/* Whether printed parameter i depends on a model parameter the record does
 * not determine. */
static bool on_undetermined(jacobian_t J, uint32_t i, const pdt_ident_std_t *s)
{
    bool hit = false;
    for (uint32_t j = 0u; j < s->count; j++) {
        if ((J[i][j] != PDT_R(0.0)) && !pdt_finite(s->std[j])) {
            hit = true;
        }
    }
    return hit;
}

/* J cov J^T where both rows exist. */
static void propagate(jacobian_t J, const pdt_ident_std_t *s, pdt_ident_printed_t *p)
{
    for (uint32_t i = 0u; i < N_PAR; i++) {
        for (uint32_t k = 0u; k < N_PAR; k++) {
            pdt_real_t c = PDT_R(0.0);
            for (uint32_t j = 0u; j < s->count; j++) {
                for (uint32_t l = 0u; l < s->count; l++) {
                    c += J[i][j] * s->cov[j][l] * J[k][l];
                }
            }
            const bool held = on_undetermined(J, i, s) || on_undetermined(J, k, s);
            p->cov[i][k] = held ? (pdt_real_t)NAN : c;
        }
    }
    for (uint32_t i = 0u; i < N_PAR; i++) {
        const bool exists = (p->have & ((uint32_t)1u << i)) != 0u;
        if (!exists) {
            p->std[i] = (pdt_real_t)NAN;
        } else if (on_undetermined(J, i, s) || !pdt_finite(p->cov[i][i])) {
            p->std[i] = (pdt_real_t)INFINITY;
        } else if (p->std[i] == PDT_R(0.0)) {
            p->std[i] = pdt_sqrt(p->cov[i][i] > PDT_R(0.0) ? p->cov[i][i] : PDT_R(0.0));
        } else {
            /* set where the derivative does not exist */
        }
    }
}

pdt_status_t pdt_ident_std_printed(const pdt_model_t *m, const pdt_ident_std_t *s,
                                   pdt_ident_printed_t *out)
{
    if ((m == NULL) || (s == NULL) || (out == NULL) || (pdt_model_check(m) != PDT_OK)) {
        return PDT_ERR_ARG;
    }
    if (s->count != pdt_model_kind_params(m->kind) + 1u) { /* and y0 */
        return PDT_ERR_ARG;
    }
    /* Nothing can fail from here: *out is built in place. */
    out->have = 0u;
    for (uint32_t i = 0u; i < N_PAR; i++) {
        out->std[i] = PDT_R(0.0);
        for (uint32_t k = 0u; k < N_PAR; k++) {
            out->cov[i][k] = PDT_R(0.0);
        }
    }
    jacobian_t J = {{0}};
    pdt_model_view_t v;
    pdt_model_view(m, &v);
    if (v.lags == 1u) {
        lag_rows(out, J);
    } else {
        pair_rows(&v, out, J);
    }
    set_row(out, PDT_IDENT_PAR_Y0);
    propagate(J, s, out);
    return PDT_OK;
}
