/*
 * Port surface for the Cortex-M4F on the MPS2 AN386 image, as run by QEMU
 * (-machine mps2-an386 -semihosting-config enable=on,target=native).
 *
 * Console and exit go through Arm semihosting (bkpt 0xAB): SYS_WRITE0 for
 * text, SYS_EXIT / SYS_EXIT_EXTENDED for the status. On a board without a
 * debugger attached, semihosting calls fault: such a firmware replaces
 * pdt_port_write and pdt_port_exit with a UART and a reset.
 *
 * Ticks: the DWT cycle counter when it counts, else SysTick on the core
 * clock with its wraps counted in an interrupt. QEMU does not model the
 * DWT, so there it is SysTick; with -icount shift=0 QEMU's clock advances
 * 1 ns per instruction, so 25 MHz ticks are then 40 instructions each.
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "pdt_port.h"
#include "pdt_port_cm4.h"
#include "pdt_port_common.h"
#include "pdt_port_target.h"

/* ARMv7-M and ARMv8-M Mainline have the DWT cycle counter; ARMv6-M
 * (Cortex-M0/M0+) has none, and its debug registers are not to be touched. */
#if defined(__ARM_ARCH_7M__) || defined(__ARM_ARCH_7EM__) || defined(__ARM_ARCH_8M_MAIN__)
#define PDT_CM4_HAVE_DWT 1
#else
#define PDT_CM4_HAVE_DWT 0
#endif

void pdt_cm4_systick_handler(void);

#define DEMCR      (*(volatile uint32_t *)0xE000EDFCu)
#define DWT_CTRL   (*(volatile uint32_t *)0xE0001000u)
#define DWT_CYCCNT (*(volatile uint32_t *)0xE0001004u)
#define SYST_CSR   (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR   (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR   (*(volatile uint32_t *)0xE000E018u)

#define SCB_ICSR           (*(volatile uint32_t *)0xE000ED04u)
#define SCB_ICSR_PENDSTSET (1u << 26)

#define SYST_RELOAD 0x00FFFFFFu

/* Semihosting operations and exit reasons (Arm semihosting spec v2). */
#define SEMI_SYS_WRITE0           0x04u
#define SEMI_SYS_EXIT             0x18u
#define SEMI_SYS_EXIT_EXTENDED    0x20u
#define SEMI_ADP_APPLICATION_EXIT 0x20026u
#define SEMI_ADP_RUNTIME_ERROR    0x20023u

/* The port's only state: set once by pdt_port_init, and the SysTick wrap
 * count the interrupt advances. */
static volatile uint32_t g_counter;
static volatile uint32_t g_systick_wraps;
/* Upper half of the widened DWT count and the last value seen. */
static volatile uint32_t g_dwt_high;
static volatile uint32_t g_dwt_last;

static uint32_t semihost(uint32_t op, const void *arg)
{
    uint32_t ret;
    __asm volatile("mov r0, %1\n\t"
                   "mov r1, %2\n\t"
                   "bkpt 0xAB\n\t"
                   "mov %0, r0"
                   : "=r"(ret)
                   : "r"(op), "r"(arg)
                   : "r0", "r1", "memory");
    return ret;
}

void pdt_port_init(void)
{
    if (g_counter != PDT_CM4_COUNTER_NONE) {
        return;
    }
#if PDT_CM4_HAVE_DWT
    /* Try the cycle counter: trace enable, reset, start, and see whether
     * it moves over a short busy loop. */
    DEMCR |= (1u << 24);
    DWT_CYCCNT = 0u;
    DWT_CTRL |= 1u;
    for (volatile uint32_t i = 0; i < 64u; i++) {
    }
    if (DWT_CYCCNT != 0u) {
        g_dwt_high = 0u;
        g_dwt_last = DWT_CYCCNT;
        g_counter = PDT_CM4_COUNTER_DWT;
        return;
    }
#endif
    g_systick_wraps = 0u;
    SYST_CSR = 0u;
    SYST_RVR = SYST_RELOAD;
    SYST_CVR = 0u;
    /* enable, interrupt on wrap, core clock */
    SYST_CSR = 7u;
    g_counter = PDT_CM4_COUNTER_SYSTICK;
}

pdt_cm4_counter_t pdt_cm4_counter(void)
{
    return (pdt_cm4_counter_t)g_counter;
}

void pdt_cm4_systick_handler(void)
{
    g_systick_wraps = g_systick_wraps + 1u;
}

void pdt_port_write(const char *text, size_t len)
{
    /* SYS_WRITE0 takes a NUL-terminated string: send it in pieces. */
    char chunk[65];
    size_t n = 0;
    for (size_t i = 0; i < len; i++) {
        if (text[i] != '\0') {
            chunk[n++] = text[i];
        }
        if (n == sizeof chunk - 1u || (i + 1u == len && n > 0u)) {
            chunk[n] = '\0';
            (void)semihost(SEMI_SYS_WRITE0, chunk);
            n = 0;
        }
    }
}

uint64_t pdt_port_ticks(void)
{
    switch (g_counter) {
    case PDT_CM4_COUNTER_DWT: {
        /* Widened on each call: callers read it at least every 2^32
         * cycles (172 s at 25 MHz) or lose a wrap. */
        uint32_t now = DWT_CYCCNT;
        if (now < g_dwt_last) {
            g_dwt_high = g_dwt_high + 1u;
        }
        g_dwt_last = now;
        return ((uint64_t)g_dwt_high << 32) | now;
    }
    case PDT_CM4_COUNTER_SYSTICK: {
        uint32_t wraps;
        uint32_t cvr;
        bool pending;
        /* Reread if the wrap interrupt ran in between. */
        do {
            wraps = g_systick_wraps;
            cvr = SYST_CVR;
            pending = (SCB_ICSR & SCB_ICSR_PENDSTSET) != 0u;
        } while (wraps != g_systick_wraps);
        /* The interrupt comes as the count reaches 0, one tick before the
         * reload, so a wrap is counted at 0: the period's elapsed ticks are
         * 0 there and RELOAD + 1 - cvr after the reload. A wrap whose
         * interrupt is still pending (masked, or not taken yet) is counted
         * here: the count is then at 0 or just reloaded. */
        if (pending && (cvr == 0u || cvr > SYST_RELOAD / 2u)) {
            wraps++;
        }
        uint32_t elapsed = cvr == 0u ? 0u : SYST_RELOAD + 1u - cvr;
        return (uint64_t)wraps * (SYST_RELOAD + 1u) + elapsed;
    }
    default:
        return 0u;
    }
}

const char *pdt_port_counter_name(void)
{
    switch (g_counter) {
    case PDT_CM4_COUNTER_DWT:
        return "the DWT cycle counter";
    case PDT_CM4_COUNTER_SYSTICK:
        return "SysTick";
    default:
        return "none";
    }
}

uint64_t pdt_port_counter_wrap(void)
{
    return g_counter == PDT_CM4_COUNTER_SYSTICK ? (uint64_t)SYST_RELOAD + 1u : 0u;
}

uint64_t pdt_port_ticks_per_second(void)
{
    return g_counter == PDT_CM4_COUNTER_NONE ? 0u : PDT_CM4_CORE_HZ;
}

void pdt_port_assert_failed(const char *expr, const char *file, int line)
{
    pdt_port_report_assert(expr, file, line);
    pdt_port_exit(2);
}

void pdt_port_exit(int status)
{
    if (status == 0) {
        (void)semihost(SEMI_SYS_EXIT, (const void *)(uintptr_t)SEMI_ADP_APPLICATION_EXIT);
    } else {
        /* SYS_EXIT carries no status on 32-bit targets; the extended call
         * does. A host without it returns, and the plain call then reports
         * a run-time error, which QEMU turns into exit status 1. */
        uint32_t block[2] = {SEMI_ADP_APPLICATION_EXIT, (uint32_t)status};
        (void)semihost(SEMI_SYS_EXIT_EXTENDED, block);
        (void)semihost(SEMI_SYS_EXIT, (const void *)(uintptr_t)SEMI_ADP_RUNTIME_ERROR);
    }
    for (;;) {
        __asm volatile("wfi");
    }
}
