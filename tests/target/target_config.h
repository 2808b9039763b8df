/*
 * Sizes of the target test program per core, and the memory its
 * identification and autotune checks share (they run one at a time).
 * PDT_TARGET_SMALL (set by port/CMakeLists.txt for the Cortex-M0 with
 * 16 KiB of RAM) gives the small program: records of 200 samples, an
 * autotune of capacity 128, no vector or cost-work checks (their tables
 * and records do not fit).
 */
#ifndef PDT_TARGET_CONFIG_H
#define PDT_TARGET_CONFIG_H

#include "pdt/pdt.h"
#include "sim_process.h"

#ifndef PDT_TARGET_SMALL
#define PDT_TARGET_SMALL 0
#endif

#if PDT_TARGET_SMALL
#define TARGET_IDENT_N         200u /* samples of the identified records */
#define TARGET_AT_CAPACITY     112u /* samples the autotune records */
/* The small program identifies without the screen for gross errors and
 * refuses missing samples (no_screen, refuse_missing): the workspace then
 * holds no copy of y, n + n / 16 reals that 16 KiB do not have. */
#define TARGET_LEAN            1
#define TARGET_SCREEN_BYTES(n) (((n) + (n) / 16u) * sizeof(pdt_real_t))
#else
#define TARGET_IDENT_N         1000u
#define TARGET_AT_CAPACITY     600u
#define TARGET_LEAN            0
#define TARGET_SCREEN_BYTES(n) 0u
#endif

/* The identification checks' memory (check_ident.c). */
typedef struct target_ident_mem {
    pdt_ident_t ctx;
    pdt_real_t u[TARGET_IDENT_N];
    pdt_real_t y[TARGET_IDENT_N];
    pdt_real_t work[(PDT_IDENT_WORKSPACE_SIZE(TARGET_IDENT_N, PDT_IDENT_POPULATION_SOPDT) -
                     TARGET_SCREEN_BYTES(TARGET_IDENT_N)) /
                        sizeof(pdt_real_t) +
                    1u];
} target_ident_mem_t;

/* One autotune's record (check_autotune.c). */
typedef struct target_at_run {
    pdt_status_t st;
    pdt_autotune_result_t res;
    uint32_t scans;
    uint64_t worst[7]; /* ticks of the slowest call in each phase */
    uint32_t calls[7];
    uint32_t max_evals;    /* most cost evaluations in one call */
    uint64_t worst_search; /* ticks of the slowest identify call that
                            * evaluated (the search's, not a preparation or
                            * a validation) */
    uint64_t worst_valid;  /* ticks of the slowest identify call after the
                            * searches: the validation in steps, the order's
                            * choice and the disturbance check */
    uint64_t worst_init;   /* ticks of the slowest identify call that began
                            * an identification (pdt_ident_init) */
    uint64_t worst_step;   /* ticks of the slowest other identify call */
    size_t stack;          /* bytes below the run's frame */
} target_at_run_t;

/* The autotune checks' memory (check_autotune.c). */
typedef struct target_autotune_mem {
    pdt_autotune_t at;
    pdt_autotune_config_t cfg;
    target_at_run_t run;
    sim_process_t process; /* the plant of the check running */
    pdt_real_t work[(PDT_AUTOTUNE_WORKSPACE_SIZE(TARGET_AT_CAPACITY, PDT_IDENT_POPULATION_SOPDT) -
                     TARGET_SCREEN_BYTES(TARGET_AT_CAPACITY)) /
                        sizeof(pdt_real_t) +
                    1u];
} target_autotune_mem_t;

typedef union target_arena {
    target_ident_mem_t ident;
    target_autotune_mem_t autotune;
} target_arena_t;

/* The one instance (target_main.c). */
extern target_arena_t t_arena;

#endif /* PDT_TARGET_CONFIG_H */
