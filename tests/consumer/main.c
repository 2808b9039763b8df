/* A firmware-style consumer of pdtfit: identifies a FOPDT from a record it
 * makes itself, in static memory. Built by tools/check_consumers.sh through
 * add_subdirectory, find_package, pkg-config and for bare-metal Cortex-M. */
#include "pdt/pdt.h"

#define N 400u

static pdt_real_t g_u[N];
static pdt_real_t g_y[N];
static unsigned char g_work[PDT_IDENT_WORKSPACE_SIZE(N, PDT_IDENT_POPULATION_SOPDT)];
static pdt_ident_t g_ident;

static int consumer_run(void)
{
    pdt_ident_config_t cfg;
    pdt_ident_data_t data = {g_u, g_y, N};
    pdt_ident_result_t res;
    pdt_real_t x = (pdt_real_t)0;
    size_t k;
    /* y = 2 / (5 s + 1) e^{-1 s} u at Ts = 0.1 s, u a step at k = 20. */
    for (k = 0u; k < N; k++) {
        g_u[k] = (k >= 20u) ? (pdt_real_t)1 : (pdt_real_t)0;
        g_y[k] = x;
        if (k >= 10u) {
            x += ((pdt_real_t)2 * g_u[k - 10u] - x) * (pdt_real_t)0.0198013;
        }
    }
    pdt_ident_config_default(&cfg);
    cfg.Ts = (pdt_real_t)0.1;
    if (pdt_identify(&g_ident, &cfg, &data, g_work, sizeof g_work, &res) != PDT_OK) {
        return 1;
    }
    return (res.model.p.fopdt.K > (pdt_real_t)1.9 && res.model.p.fopdt.K < (pdt_real_t)2.1) ? 0 : 2;
}

int main(void)
{
    return consumer_run();
}
