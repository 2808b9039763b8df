/*
 * A minimal firmware loop running one pdtfit autotune on a heater: PRBS
 * experiment, FOPDT or SOPDT model as the data choose, SIMC PI gains, then
 * the PID (pdt_pid) that runs them, taking over without a bump. The board
 * functions at the bottom stand for the application's own I/O, set-point
 * and timer; replace them.
 * Built (not run) by tests/CMakeLists.txt so that it keeps compiling.
 */
#include "pdt/pdt.h"

#define SCAN_PERIOD_S 0.5f /* the control task's period */
#define CAPACITY      600u /* samples recorded: 600 x 0.5 s = 5 min */

/* The workspace: one static array, sized by the compile-time bound (the
 * record plus the larger of either model's identification and the
 * validation for CAPACITY samples), checked against the exact size query
 * at run time. */
static pdt_real_t
    work[PDT_AUTOTUNE_WORKSPACE_SIZE(CAPACITY, PDT_IDENT_POPULATION_SOPDT) / sizeof(pdt_real_t) +
         1u];
static pdt_autotune_t at;
static pdt_pid_t pid;

float board_read_temperature(void);
float board_setpoint(void);
void board_write_heater(float percent);
void board_wait_next_scan(void);

int main(void)
{
    pdt_autotune_config_t cfg;
    pdt_autotune_config_default(&cfg);
    cfg.Ts = SCAN_PERIOD_S;
    cfg.decimation = 1u;
    cfg.capacity = CAPACITY;
    cfg.settle = 20u; /* 10 s at rest first */
    cfg.excite.kind = PDT_EXCITE_PRBS;
    cfg.excite.amplitude = 5.0f; /* +/- 5 % heater around the operating point */
    cfg.excite.prbs_bits = 7u;
    cfg.excite.prbs_hold = 8u; /* 4 s chips, 127 chips = 508 s */
    cfg.u_min = 0.0f;          /* the heater's range, % */
    cfg.u_max = 100.0f;
    cfg.pv_min = 20.0f; /* what the process may see, deg C */
    cfg.pv_max = 90.0f;
    cfg.max_scans = 2000u; /* give up after 1000 s */
    /* The model order is the data's by default (a FOPDT and a SOPDT are
     * identified); to fix it: cfg.order_auto = false and cfg.ident.model. */
    cfg.tune.rule = PDT_TUNE_SIMC;
    cfg.tune.form = PDT_TUNE_PI;

    float u_now = 35.0f; /* the output that holds the process at rest now */
    size_t need = pdt_autotune_workspace_size(&cfg);
    if (need == 0u || need > sizeof work ||
        pdt_autotune_init(&at, &cfg, u_now, work, need) != PDT_OK) {
        return 1; /* a configuration error: fix cfg */
    }

    pdt_autotune_result_t res;
    bool tuned = false;
    for (;;) {
        float u;
        pdt_status_t st = pdt_autotune_scan(&at, board_read_temperature(), &u);
        board_write_heater(u); /* always apply it, also after a failure */
        if (st == PDT_OK) {
            (void)pdt_autotune_result(&at, &res);
            /* The PID takes over from the output in service (u): the
             * integral starts where the autotune left the heater, so the
             * first automatic output equals it (no bump). */
            pdt_pid_config_t pc;
            pdt_pid_config_default(&pc);
            pc.Ts = SCAN_PERIOD_S;
            pc.u_min = cfg.u_min;
            pc.u_max = cfg.u_max;
            tuned = pdt_pid_init_from_gains(&pid, &pc, &res.tune.ideal, PDT_PID_IDEAL, u) == PDT_OK;
            break;
        }
        if (st != PDT_RUNNING) {
            /* aborted or refused: u is the operating point; report
             * pdt_status_str(st) and res.failed_in */
            (void)pdt_autotune_result(&at, &res);
            break;
        }
        board_wait_next_scan();
    }
    for (;;) {
        board_wait_next_scan();
        if (tuned) {
            float u;
            /* On a failed sensor (NaN) the PID refuses and u keeps the last
             * output: hold it. */
            if (pdt_pid_update(&pid, board_setpoint(), board_read_temperature(), &u) == PDT_OK) {
                board_write_heater(u);
            }
        }
    }
}

/* Stand-ins so that the example links on a host. */
float board_read_temperature(void)
{
    return 40.0f;
}

float board_setpoint(void)
{
    return 45.0f;
}

void board_write_heater(float percent)
{
    (void)percent;
}

void board_wait_next_scan(void)
{
}
