/*
 * pdtfit model reduction: a FOPDT or SOPDT model from a known detailed
 * model, by Skogestad's half rule (2003) or by the frequency-response method
 * of Sung et al. (1998), the two references of the paper's Tables 1-3.
 *
 * The detailed model (pdt_reduce_plant_t) is
 *
 *     G(s) = k * prod_j (T_j s + 1) / prod_i (tau_i s + 1) * e^{-theta0 s}
 *
 * with lag time constants tau_i > 0 and zero time constants T_j != 0: a
 * positive T_j is a left-half-plane zero, a negative one a right-half-plane
 * (inverse-response) zero. The DC gain is k. Times in seconds, frequencies
 * in rad/s. The equations, the conventions chosen where the sources leave a
 * choice, and a worked example are in docs/reduce.md.
 *
 * Both calls are pure functions of their inputs: no state, no workspace,
 * bounded work, and the outputs are written only on PDT_OK.
 */
#ifndef PDT_REDUCE_H
#define PDT_REDUCE_H

#include "pdt/pdt_common.h"
#include "pdt/pdt_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Passes of the half rule's fixed-point iteration on the effective delay
 * (the left-half-plane zero rules depend on it; see docs/reduce.md). */
#define PDT_REDUCE_MAX_PASSES 48u

/* Default number of frequencies of Sung's least squares. */
#define PDT_REDUCE_N_FREQ_DEFAULT 10u

/* Rules applied to a left-half-plane zero (T0 s + 1) cancelled against a lag
 * (tau0 s + 1), tau_c the effective delay (bits of pdt_reduce_info_t.rules).
 * The ratio becomes: */
#define PDT_REDUCE_RULE_T1  0x01u /* T0 / tau0,   T0 >= tau0 >= tau_c */
#define PDT_REDUCE_RULE_T1A 0x02u /* T0 / tau_c,  T0 >= tau_c >= tau0 */
#define PDT_REDUCE_RULE_T1B 0x04u /* 1,           tau_c >= T0 >= tau0 */
#define PDT_REDUCE_RULE_T2  0x08u /* T0 / tau0,   tau0 >= T0 >= 5 tau_c */
#define PDT_REDUCE_RULE_T3                                                                         \
    0x10u /* (t / tau0) / ((t - T0) s + 1),
                                   * t = min(tau0, 5 tau_c) >= T0 */

/* The detailed model. The arrays are the caller's and are only read. */
typedef struct pdt_reduce_plant {
    pdt_real_t k;            /* DC gain, output units per input unit, finite */
    const pdt_real_t *lags;  /* tau_i, s, each finite and > 0, any order */
    size_t n_lags;           /* >= 1 */
    const pdt_real_t *zeros; /* T_j of (T_j s + 1), s, each finite and != 0
                               * (< 0: right-half-plane zero); may be NULL
                               * when n_zeros is 0 */
    size_t n_zeros;
    pdt_real_t theta0; /* dead time, s, finite and >= 0 */
} pdt_reduce_plant_t;

typedef struct pdt_reduce_config {
    pdt_model_kind_t model; /* FOPDT or SOPDT. Default FOPDT */
    pdt_real_t h;           /* half rule: period of the digital controller
                             * that will use the model, s, >= 0; h / 2 is
                             * added to the dead time. 0: continuous
                             * controller. Not used by Sung. Default 0 */
    uint32_t n_freq;        /* Sung: frequencies M of the least squares,
                             * evenly spaced in (0, w_u]; 0 means
                             * PDT_REDUCE_N_FREQ_DEFAULT (10, the grid that
                             * reproduces the paper); SOPDT needs >= 2;
                             * at most PDT_REDUCE_MAX_FREQ (pdt_config.h,
                             * 4096 by default).
                             * Not used by the half rule. Default 0 */
} pdt_reduce_config_t;

/* What a reduction did, for diagnostics. */
typedef struct pdt_reduce_info {
    uint32_t rules;  /* half rule: PDT_REDUCE_RULE_* bits of the rules used
                       * in the final pass; 0 without left-half-plane zeros
                       * and for Sung */
    uint32_t passes; /* half rule: passes made, 1 .. PDT_REDUCE_MAX_PASSES;
                       * 0 for Sung */
    bool converged;  /* half rule: the final pass reproduced the effective
                       * delay its rules assumed (false: the pass limit
                       * stopped it; the last pass is returned). Sung: true */
    bool fallback;   /* Sung: a SOPDT was asked but the fit has none (see
                       * pdt_reduce_sung); the output is the FOPDT */
    pdt_real_t w_u;  /* Sung: ultimate frequency, rad/s; 0 for the half rule */
} pdt_reduce_info_t;

/* Fills cfg with the documented defaults. Does nothing for NULL. */
void pdt_reduce_config_default(pdt_reduce_config_t *cfg);

/* Skogestad's half rule. Left-half-plane zeros are first cancelled, each
 * against one lag (the closest lag >= T0 not yet used, else the largest
 * smaller one left), by rules T1 .. T3 above with tau_c the effective delay
 * of the result; as that delay depends on the rules chosen, the rules are
 * applied again with each new delay until it repeats, at most
 * PDT_REDUCE_MAX_PASSES times. Right-half-plane zeros and the small lags
 * then go into the dead time:
 *   FOPDT: tau = l1 + l2 / 2,
 *          Td = theta0 + l2 / 2 + sum_{i>=3} l_i + sum |T_rhp| + h / 2;
 *   SOPDT: time constants l1 and l2 + l3 / 2,
 *          Td = theta0 + l3 / 2 + sum_{i>=4} l_i + sum |T_rhp| + h / 2,
 * l1 >= l2 >= ... the lags left after the cancellations. The gain is k times
 * the gains of the rules. A SOPDT is returned in form (2) (from its two time
 * constants by pdt_model_sopdt_from_tc).
 *
 * plant: the detailed model; cfg: model kind and h (NULL: defaults);
 * out: the reduced model (caller's); info: diagnostics, may be NULL.
 * Work: O(n_lags^2 + n_zeros^2) per pass.
 * Returns PDT_OK;
 *   PDT_ERR_ARG for NULL plant, out, lags (or zeros with n_zeros > 0), an
 *     unknown model kind, a lag <= 0, a zero time constant of 0, theta0 < 0,
 *     h < 0, or a result that does not fit the real type;
 *   PDT_ERR_NONFINITE for a non-finite k, lag, zero, theta0 or h;
 *   PDT_ERR_LENGTH for n_lags = 0 or n_lags > PDT_REDUCE_MAX_LAGS;
 *   PDT_ERR_NO_FORM when a left-half-plane zero finds no lag left to cancel
 *     against, or fewer lags remain than the model's order (e.g. a SOPDT
 *     from a single lag). */
pdt_status_t pdt_reduce_half_rule(const pdt_reduce_plant_t *plant, const pdt_reduce_config_t *cfg,
                                  pdt_model_t *out, pdt_reduce_info_t *info);

/* The ultimate frequency w_u (rad/s): the first frequency at which the phase
 * of G(jw) / k, taken continuously from 0 at w = 0 as
 *   sum_j atan(T_j w) - sum_i atan(tau_i w) - w theta0,
 * reaches -pi. Found by a geometric scan (ratio 2^(1/8)) from
 * 1e-3 / (sum tau_i + sum |T_j| + theta0) up to 1e4 / (smallest time
 * constant) (or further with a dead time, far enough that the delay alone
 * reaches -pi), then 64 bisection steps at most.
 * Work: O((n_lags + n_zeros) * scan points), the scan bounded to 4096 points.
 * Returns PDT_OK; PDT_ERR_ARG, PDT_ERR_NONFINITE, PDT_ERR_LENGTH as for
 * pdt_reduce_half_rule (no upper limit on n_lags); PDT_ERR_NO_FORM when the
 * phase does not reach -pi in that range (e.g. one or two lags and no dead
 * time). *w_u is written only on PDT_OK. */
pdt_status_t pdt_reduce_ultimate(const pdt_reduce_plant_t *plant, pdt_real_t *w_u);

/* Sung et al.'s reduction from the frequency response up to w_u
 * (pdt_reduce_ultimate), on M = cfg->n_freq frequencies w_i = i w_u / M:
 *   FOPDT: K = k; tau^2 the least-squares solution of
 *          K^2 - |G_i|^2 = tau^2 w_i^2 |G_i|^2;
 *          Td = (pi - atan(tau w_u)) / w_u.
 *   SOPDT: least squares of K^2 - |G_i|^2 = |G_i|^2 (p1 w_i^2 + p2 w_i^4),
 *          then K e^{-Td s} / (tau^2 s^2 + 2 zeta tau s + 1) with
 *          tau = p2^(1/4), zeta^2 = (p1 / tau^2 + 2) / 4 and
 *          Td = (pi - atan2(2 zeta tau w_u, 1 - tau^2 w_u^2)) / w_u,
 *          in form (2). When p2 <= 0 or zeta^2 <= 0 no such SOPDT exists:
 *          the FOPDT is returned instead (out->kind = PDT_MODEL_FOPDT,
 *          info->fallback = true) with PDT_OK.
 * A negative k is reduced as -G with the sign put back into the gain.
 * cfg->h is not used.
 * plant, cfg (NULL: defaults), out, info (may be NULL) as for
 * pdt_reduce_half_rule.
 * Work: that of pdt_reduce_ultimate plus O(M (n_lags + n_zeros)).
 * Returns PDT_OK; PDT_ERR_ARG, PDT_ERR_NONFINITE, PDT_ERR_LENGTH as for
 * pdt_reduce_ultimate, and PDT_ERR_ARG also for n_freq = 1 with a SOPDT,
 * PDT_ERR_LENGTH also for n_freq > PDT_REDUCE_MAX_FREQ;
 * PDT_ERR_NO_FORM when there is no ultimate frequency, k = 0 (nothing to
 * fit), or the magnitude does not fall below |k| on the grid (tau^2 <= 0). */
pdt_status_t pdt_reduce_sung(const pdt_reduce_plant_t *plant, const pdt_reduce_config_t *cfg,
                             pdt_model_t *out, pdt_reduce_info_t *info);

#ifdef __cplusplus
}
#endif

#endif /* PDT_REDUCE_H */
