/* A model on a record by the library's own calls (the command line and the
 * Python binding). */
#ifndef PDTCLI_MODEL_RECORD_H
#define PDTCLI_MODEL_RECORD_H

#include <stddef.h>

#include "pdt/pdt.h"

/* The output of model m (sampling period Ts) from rest on u - u0, plus y0,
 * into ysim (n reals) unless NULL (pdt_cost_simulate), and the fit
 * pdt_identify reports for its answers (pdt_cost_fit, percent) into *fit
 * unless NULL. Returns the library's status, PDT_ERR_NOMEM when memory
 * runs out. */
pdt_status_t pdtcli_model_on_record(const pdt_model_t *m, double Ts, const pdt_real_t *u,
                                    const pdt_real_t *y, size_t n, pdt_real_t u0, pdt_real_t y0,
                                    pdt_real_t *ysim, pdt_real_t *fit);

#endif /* PDTCLI_MODEL_RECORD_H */
