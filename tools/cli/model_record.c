/* A model on a record, by the library's own calls: shared by the command
 * line and the Python binding. */
#include <stdlib.h>

#include "model_record.h"

pdt_status_t pdtcli_model_on_record(const pdt_model_t *m, double Ts, const pdt_real_t *u,
                                    const pdt_real_t *y, size_t n, pdt_real_t u0, pdt_real_t y0,
                                    pdt_real_t *ysim, pdt_real_t *fit)
{
    pdt_cost_config_t cc;
    pdt_cost_config_default(&cc);
    cc.Ts = (pdt_real_t)Ts;
    cc.u0 = u0;
    cc.y0 = y0;
    cc.delay_max = 0;
    cc.whole_record = true;
    cc.use_frequency = false;
    cc.kind = PDT_COST_SIMULATION;
    pdt_cost_t cost;
    pdt_discrete_t d;
    /* the cost's workspace, then n reals of scratch for the fit */
    const size_t wlen = pdt_cost_workspace_size(&cc, n);
    pdt_real_t *work = wlen ? malloc(wlen + n * sizeof *work) : NULL;
    pdt_status_t st = work ? pdt_cost_init(&cost, &cc, u, y, n, work, wlen) : PDT_ERR_NOMEM;
    if (st == PDT_OK && ysim) {
        st = pdt_discrete_init(m, (pdt_real_t)Ts, &d);
        if (st == PDT_OK) st = pdt_cost_simulate(&cost, &d, ysim);
    }
    if (st == PDT_OK && fit) st = pdt_cost_fit(&cost, m, 0, work + wlen / sizeof *work, fit);
    free(work);
    return st;
}
