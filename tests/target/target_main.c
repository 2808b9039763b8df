/*
 * pdtfit's target test program: runs on the Cortex-M4F (QEMU mps2-an386,
 * see docs/port.md), one line per check on the semihosting console, and
 * exits 0 only if every check passed. Ends with the stack high-water mark.
 */
#include "pdt/pdt.h"
#include "pdt_port.h"
#include "pdt_port_target.h"
#include "target_checks.h"
#include "target_config.h"
#include "target_util.h"

/* The memory the identification and autotune checks share
 * (target_config.h). */
target_arena_t t_arena;

typedef struct target_check {
    const char *name;
    int (*run)(void); /* returns the number of failed checks */
} target_check_t;

/* Reads the ticks `reads` times or, with until > 0, until they pass
 * `until`; false if they ever step back. *last gets the last value. */
static bool ticks_forward(uint32_t reads, uint64_t until, uint64_t *last)
{
    uint64_t prev = pdt_port_ticks();
    bool monotonic = true;
    for (uint32_t i = 0; until > 0u ? prev <= until : i < reads; i++) {
        /* Far from the target, wait between reads: each read is a device
         * access, slow to emulate. */
        if (until > 0u && until - prev > 50000u) {
            for (volatile uint32_t j = 0; j < 2000u; j++) {
            }
        }
        uint64_t now = pdt_port_ticks();
        monotonic = monotonic && now >= prev;
        prev = now;
    }
    *last = prev;
    return monotonic;
}

/* The port itself: a counter was found, runs at its stated rate and moves
 * forward. */
static int check_port(void)
{
    uint64_t hz = pdt_port_ticks_per_second();
    uint64_t t0 = pdt_port_ticks();
    uint64_t t1 = 0;
    bool monotonic = ticks_forward(20000u, 0u, &t1);
    bool ok = hz > 0u && monotonic && t1 > t0;
    tline_t l;
    tl_init(&l);
    tl_str(&l, "port: ticks at ");
    tl_uint(&l, hz);
    tl_str(&l, " Hz, 20000 reads in ");
    tl_uint(&l, t1 - t0);
    tl_str(&l, " ticks, ");
    tl_str(&l, monotonic ? "never backwards" : "went BACKWARDS");
    return t_verdict(ok, &l);
}

/* SysTick's 24-bit count wraps every 2^24 ticks (0.67 s at 25 MHz, 671 M
 * instructions under -icount shift=0); the widened count must go on
 * rising across the next wrap. Run last, when most of the way there. */
static int check_port_wrap(void)
{
    const uint64_t period = pdt_port_counter_wrap();
    if (period == 0u) {
        return 0; /* a counter the port does not widen by its wraps */
    }
    uint64_t t0 = pdt_port_ticks();
    uint64_t until = (t0 / period + 1u) * period + 1000u;
    uint64_t t1 = 0;
    bool monotonic = ticks_forward(0u, until, &t1);
    tline_t l;
    tl_init(&l);
    tl_str(&l, "port: ticks from ");
    tl_uint(&l, t0);
    tl_str(&l, " to ");
    tl_uint(&l, t1);
    tl_str(&l, " across a SysTick wrap, ");
    tl_str(&l, monotonic ? "never backwards" : "went BACKWARDS");
    return t_verdict(monotonic && t1 > until, &l);
}

/* The figures of the port table (docs/port.md): the memory the checks
 * give the library, for the record lengths this core runs. */
static int check_memory(void)
{
    tline_t l;
    tl_init(&l);
    tl_str(&l, "memory: pdt_ident_t ");
    tl_uint(&l, sizeof(pdt_ident_t));
    tl_str(&l, " B, pdt_autotune_t ");
    tl_uint(&l, sizeof(pdt_autotune_t));
    tl_str(&l, " B; workspace: identification of ");
    tl_uint(&l, TARGET_IDENT_N);
    tl_str(&l, " samples (SOPDT) ");
    tl_uint(&l, PDT_IDENT_WORKSPACE_SIZE(TARGET_IDENT_N, PDT_IDENT_POPULATION_SOPDT));
    tl_str(&l, " B, autotune of capacity ");
    tl_uint(&l, TARGET_AT_CAPACITY);
    tl_str(&l, " ");
    tl_uint(&l, PDT_AUTOTUNE_WORKSPACE_SIZE(TARGET_AT_CAPACITY, PDT_IDENT_POPULATION_SOPDT));
    tl_str(&l, " B; the checks' shared memory ");
    tl_uint(&l, sizeof t_arena);
    tl_str(&l, " B");
    t_info(&l);
    return 0;
}

/*
 * The registry of target checks, run in this order. To add one (e.g. an
 * autotune of a simulated plant once that module exists), write
 * `int target_check_<name>(void)` in a new tests/target/check_<name>.c,
 * declare it in target_checks.h, list the file in tests/target/CMakeLists.txt
 * and add a line here.
 */
/* check_autotune.c */
int target_check_autotune(void);

static const target_check_t target_checks[] = {
    {"port", check_port},
#if !PDT_TARGET_SMALL
    {"fft", target_check_fft},
    {"model", target_check_model},
    {"discrete", target_check_discrete},
    {"cost", target_check_cost},
    {"cost work at N=2000", target_check_cost_work},
#endif
    {"identification", target_check_ident},
    {"autotune", target_check_autotune},
    {"pid", target_check_pid},
    {"port counter across a wrap", check_port_wrap},
    {"memory", check_memory},
};

int main(void)
{
    pdt_port_init();
    tline_t l;
    tl_init(&l);
    tl_str(&l, "pdtfit ");
    tl_str(&l, PDT_VERSION_STRING);
    tl_str(&l, " target tests on ");
    tl_str(&l, PDT_TARGET_CORE);
    tl_str(&l, ", ");
    tl_str(&l, PDT_REAL_DOUBLE ? "double" : "float");
    tl_str(&l, " build; ticks from ");
    tl_str(&l, pdt_port_counter_name());
    tl_str(&l, " at ");
    tl_uint(&l, pdt_port_ticks_per_second());
    tl_str(&l, " Hz");
    t_info(&l);

    for (size_t i = 0; i < sizeof target_checks / sizeof target_checks[0]; i++) {
        tl_init(&l);
        tl_str(&l, "-- ");
        tl_str(&l, target_checks[i].name);
        tl_emit(&l);
        (void)target_checks[i].run();
    }

    tl_init(&l);
    size_t stack = t_stack_max();
    tl_str(&l, "stack high-water mark of the program ");
    tl_uint(&l, stack);
    tl_str(&l, " of ");
    tl_uint(&l, pdt_port_stack_size());
    tl_str(&l, " bytes");
    t_info(&l);
    /* The whole stack used means it may have overflowed into .bss. */
    bool stack_ok = stack < pdt_port_stack_size();
    if (!stack_ok) {
        tl_init(&l);
        tl_str(&l, "stack within its reserve");
        (void)t_verdict(false, &l);
    }

    tl_init(&l);
    tl_uint(&l, t_checks_run());
    tl_str(&l, " checks, ");
    tl_uint(&l, t_checks_failed());
    tl_str(&l, " failed: ");
    tl_str(&l, t_checks_failed() == 0u ? "ALL PASSED" : "FAILED");
    tl_emit(&l);
    return t_checks_failed() == 0u ? 0 : 1;
}
