/*
 * pdtfit's target test program: runs on the Cortex-M4F (QEMU mps2-an386,
 * see docs/port.md), one line per check on the semihosting console, and
 * exits 0 only if every check passed. Ends with the stack high-water mark.
 */
#include "pdt/pdt.h"
#include "pdt_port.h"
#include "pdt_port_cm4.h"
#include "target_checks.h"
#include "target_util.h"

typedef struct target_check {
    const char *name;
    int (*run)(void); /* returns the number of failed checks */
} target_check_t;

/*
 * The registry of target checks, run in this order. To add one (e.g. an
 * autotune of a simulated plant once that module exists), write
 * `int target_check_<name>(void)` in a new tests/target/check_<name>.c,
 * declare it in target_checks.h, list the file in tests/target/CMakeLists.txt
 * and add a line here.
 */
static const target_check_t target_checks[] = {
    {"fft", target_check_fft},
    {"model", target_check_model},
    {"discrete", target_check_discrete},
    {"cost", target_check_cost},
    {"cost work at N=2000", target_check_cost_work},
    {"identification", target_check_ident},
};

int main(void)
{
    pdt_port_init();
    tline_t l;
    tl_init(&l);
    tl_str(&l, "pdtfit ");
    tl_str(&l, PDT_VERSION_STRING);
    tl_str(&l, " target tests, ");
    tl_str(&l, PDT_REAL_DOUBLE ? "double" : "float");
    tl_str(&l, " build; ticks from ");
    tl_str(&l, pdt_cm4_counter() == PDT_CM4_COUNTER_DWT ? "the DWT cycle counter"
                                                       : "SysTick");
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
    tl_uint(&l, pdt_cm4_stack_size());
    tl_str(&l, " bytes");
    t_info(&l);
    /* The whole stack used means it may have overflowed into .bss. */
    bool stack_ok = stack < pdt_cm4_stack_size();
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
