/*
 * Port surface for a 32-bit RISC-V core (rv32imac, rv32imafc) on QEMU's
 * `virt` machine (-machine virt -bios none), in machine mode, with
 * picolibc: its crt0 (the hosted one) sets the stack, the global pointer, the FPU (on an F
 * core), .data, .bss and the thread-local errno, calls main and then exit,
 * which ends here in _exit. The memory map is picolibc's picolibc.ld with
 * the addresses the build passes (port/CMakeLists.txt): code from
 * 0x8000_0000, RAM from 0x8040_0000, the stack its top __stack_size bytes.
 *
 * Console and exit go through RISC-V semihosting (the ebreak between
 * slli/srai x0 marker instructions, the operations of Arm's semihosting):
 * SYS_WRITE0 for text, SYS_EXIT / SYS_EXIT_EXTENDED for the status.
 *
 * Ticks: the cycle counter (mcycle, read as rdcycle). Under QEMU with
 * -icount shift=0 it counts instructions, one per emulated nanosecond, so
 * the port states 1 GHz and the target test's ticks are instructions. On
 * silicon it counts core cycles: set PDT_RV32_CORE_HZ to the clock.
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "pdt_port.h"
#include "pdt_port_common.h"
#include "pdt_port_target.h"

#ifndef PDT_RV32_CORE_HZ
#define PDT_RV32_CORE_HZ 1000000000u
#endif

/* picolibc.ld: the top of the stack; the link defines its size. */
extern uint32_t __stack[];
extern char __stack_size[];

void _exit(int status);
void pdt_rv32_trap_handler(void);

#define SEMI_SYS_WRITE0           0x04u
#define SEMI_SYS_EXIT             0x18u
#define SEMI_SYS_EXIT_EXTENDED    0x20u
#define SEMI_ADP_APPLICATION_EXIT 0x20026u
#define SEMI_ADP_RUNTIME_ERROR    0x20023u

#define STACK_PAINT 0xC5u

/* CSR instructions: Zicsr named for the assembler, whatever -march the
 * compiler was given (the multilib's, rv32imac or rv32imafc). */
#define CSR_ASM(insn) ".option push\n\t.option arch, +zicsr\n\t" insn "\n\t.option pop"

static bool g_started;

static uintptr_t semihost(uintptr_t op, const void *arg)
{
    register uintptr_t a0 __asm("a0") = op;
    register const void *a1 __asm("a1") = arg;
    /* The three instructions uncompressed and in one page, as the
     * semihosting specification for RISC-V asks. */
    __asm volatile(".option push\n\t"
                   ".option norvc\n\t"
                   ".balign 16\n\t"
                   "slli zero, zero, 0x1f\n\t"
                   "ebreak\n\t"
                   "srai zero, zero, 0x7\n\t"
                   ".option pop"
                   : "+r"(a0)
                   : "r"(a1)
                   : "memory");
    return a0;
}

static unsigned char *stack_bottom(void)
{
    return (unsigned char *)((uintptr_t)__stack - (uintptr_t)__stack_size);
}

void pdt_port_stack_paint(void)
{
    pdt_port_paint_stack(stack_bottom(), STACK_PAINT);
}

size_t pdt_port_stack_depth(void)
{
    uintptr_t sp;
    __asm volatile("mv %0, sp" : "=r"(sp));
    return (size_t)((uintptr_t)__stack - sp);
}

size_t pdt_port_stack_size(void)
{
    return (size_t)(uintptr_t)__stack_size;
}

size_t pdt_port_stack_used(void)
{
    return pdt_port_painted_used(stack_bottom(), (const unsigned char *)__stack, STACK_PAINT);
}

void pdt_port_init(void)
{
    if (g_started) {
        return;
    }
    g_started = true;
    /* Traps report and stop instead of jumping to address 0. */
    __asm volatile(CSR_ASM("csrw mtvec, %0")::"r"((uintptr_t)pdt_rv32_trap_handler));
    pdt_port_stack_paint();
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
    uint32_t hi;
    uint32_t lo;
    uint32_t hi2;
    do {
        __asm volatile(CSR_ASM("rdcycleh %0") : "=r"(hi));
        __asm volatile(CSR_ASM("rdcycle %0") : "=r"(lo));
        __asm volatile(CSR_ASM("rdcycleh %0") : "=r"(hi2));
    } while (hi != hi2);
    return ((uint64_t)hi << 32) | lo;
}

uint64_t pdt_port_ticks_per_second(void)
{
    return g_started ? PDT_RV32_CORE_HZ : 0u;
}

const char *pdt_port_counter_name(void)
{
    return g_started ? "mcycle" : "none";
}

uint64_t pdt_port_counter_wrap(void)
{
    return 0u; /* 64 bits: no wrap to cross */
}

__attribute__((interrupt("machine"), aligned(4))) void pdt_rv32_trap_handler(void)
{
    uint32_t cause;
    uint32_t epc;
    uint32_t tval;
    __asm volatile(CSR_ASM("csrr %0, mcause") : "=r"(cause));
    __asm volatile(CSR_ASM("csrr %0, mepc") : "=r"(epc));
    __asm volatile(CSR_ASM("csrr %0, mtval") : "=r"(tval));
    pdt_port_write_text("\n*** trap\n");
    pdt_port_write_hex("mcause", cause);
    pdt_port_write_hex("mepc", epc);
    pdt_port_write_hex("mtval", tval);
    pdt_port_exit(3);
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
        /* As on the Cortex-M port: the extended call carries the status,
         * the plain one a run-time error (QEMU exit status 1). */
        uint32_t block[2] = {SEMI_ADP_APPLICATION_EXIT, (uint32_t)status};
        (void)semihost(SEMI_SYS_EXIT_EXTENDED, block);
        (void)semihost(SEMI_SYS_EXIT, (const void *)(uintptr_t)SEMI_ADP_RUNTIME_ERROR);
    }
    for (;;) {
        __asm volatile("wfi");
    }
}

/* picolibc's exit() ends here: main's status to the runner. */
void _exit(int status)
{
    pdt_port_exit(status);
}
