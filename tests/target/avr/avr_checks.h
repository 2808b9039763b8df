/*
 * The checks of the AVR target test program (ATmega2560 under simavr, see
 * docs/port.md) and the RAM they share. 8 KiB hold one check's data at a
 * time, so the checks take turns in one arena (avr_main.c) instead of each
 * owning static arrays as the Cortex-M4F program's do.
 */
#ifndef PDT_AVR_CHECKS_H
#define PDT_AVR_CHECKS_H

#include <stdint.h>

#include <avr/pgmspace.h>

#include "pdt/pdt.h"
#include "sim_plant.h"
#include "target_util.h"

/* Appends a string literal kept in flash: the lines' text would take a
 * kilobyte of RAM. */
#define TL_STR(l, s) tl_str_flash((l), PSTR(s))
void tl_str_flash(tline_t *l, const char *flash_str);

/* The identification: a FOPDT of AVR_IDENT_N samples by the default
 * configuration (SIMULATION, no frequency part) without the screen for
 * gross errors and with missing samples refused, so that the workspace
 * holds no copy of y. Its workspace, as pdt_ident_workspace_size gives it:
 * the record's 2 n reals, n more, and 2 P (genes + 3) + P for the
 * population of P = 24 and 2 genes; one real more, as the check starts the
 * workspace a byte in. */
#define AVR_IDENT_N          140u
#define AVR_IDENT_WORK_REALS (3u * AVR_IDENT_N + 11u * PDT_IDENT_POPULATION_FOPDT + 1u)
/* The screen for gross errors (pdt_ident_screen.c) keeps a filled copy of
 * y and two bit masks: n + 2 ceil(n / 32) reals more. */
#define AVR_SCREEN_REALS(n)  ((n) + 2u * (((n) + 31u) / 32u))

/* The autotune: a FOPDT order fixed and no validation (what else fits is
 * in docs/port.md), a record of AVR_AT_CAPACITY samples. Workspace: the
 * record's 2 capacity reals and the identification's as above. */
#define AVR_AT_CAPACITY   46u
#define AVR_AT_WORK_REALS (5u * AVR_AT_CAPACITY + 11u * PDT_IDENT_POPULATION_FOPDT)
/* Input history of the simulated plant: its dead time in scans + 2. */
#define AVR_AT_HIST       8u

/* One scenario of the PID vectors, copied from flash. */
#define AVR_PID_STEPS 80u

typedef union avr_arena {
    struct {
        pdt_real_t u[AVR_IDENT_N];
        pdt_real_t y[AVR_IDENT_N];
        pdt_ident_t ctx;
        pdt_real_t work[AVR_IDENT_WORK_REALS];
    } ident;
    struct {
        double cfg[28];
        double u0[1];
        int op[AVR_PID_STEPS];
        double in[3u * AVR_PID_STEPS];
        double out[AVR_PID_STEPS];
    } pid;
    struct {
        pdt_autotune_t at;
        /* The result is copied over the workspace once the run is over
         * (pdt_autotune_result reads the object only): 532 bytes the
         * stack would not have. */
        union {
            pdt_real_t work[AVR_AT_WORK_REALS];
            pdt_autotune_result_t res;
        } w;
        sim_plant_t plant;
        double hist[AVR_AT_HIST];
    } autotune;
} avr_arena_t;

extern avr_arena_t g_avr_arena;

/* check_avr_math.c: expm1 and log1p (the library's own) against numpy. */
int avr_check_math(void);

/* check_avr_ident.c: a FOPDT of AVR_IDENT_N samples against the truth. */
int avr_check_ident(void);

/* check_avr_pid.c: every scenario of the PID vectors, and one update's
 * cycles. */
int avr_check_pid(void);

/* check_avr_autotune.c: an autotune of a simulated FOPDT, and the cycles
 * of its worst scan. */
int avr_check_autotune(void);

#endif /* PDT_AVR_CHECKS_H */
