/*
 * Private to the autotune: the disturbance check of its record
 * (pdt_autotune_check.c).
 */
#ifndef PDT_AUTOTUNE_PRIV_H
#define PDT_AUTOTUNE_PRIV_H

#include "pdt/pdt_excite.h"
#include "pdt/pdt_ident.h"
#include "pdt/pdt_model.h"

/* The largest shift of the residual's level across the record: with
 * r = y - y0 - (the model m run on u - u0 at Ts), the largest difference
 * of r's mean after and before a split, over the splits that leave an
 * eighth of the record on either side, as a fraction of the range of the
 * model's output. A load that enters during the experiment or a drift
 * leaves such a shift that no model of the process removes; noise and a
 * model's small structural error do not. A shift below 6 standard errors
 * of the means (from the residual's variance) is noise: *shift is then 0.
 * *span receives the range of the model's output (pv units).
 * work: 2 data->n reals; the residual r is left in work[0 .. n). Returns
 * PDT_ERR_ARG (a model pdt_discrete_init refuses) or PDT_OK; *shift is 0
 * when the model's output does not move. O(n). */
pdt_status_t pdt_autotune_shift(const pdt_model_t *m, const pdt_ident_data_t *data, pdt_real_t Ts,
                                pdt_real_t u0, pdt_real_t y0, pdt_real_t *work, pdt_real_t *shift,
                                pdt_real_t *span);

/* Whether the residual r (n values, pdt_autotune_shift's) is a drift
 * rather than a load change: a straight line through it explains at least
 * as much of its variance as the best single level shift does. *slope is
 * the line's slope, per sample (0 below 8 samples). O(n). */
bool pdt_autotune_ramp(const pdt_real_t *r, size_t n, pdt_real_t *slope);

/* The spread of a relay's last two measured cycles: the larger of
 * |difference| / mean of their lengths and of their amplitudes; 0 for
 * fewer than two cycles. A relay without bias on an undisturbed process
 * repeats the same cycle once its transient from rest is over. O(1). */
pdt_real_t pdt_autotune_relay_spread(const pdt_excite_t *gen);

#endif /* PDT_AUTOTUNE_PRIV_H */
