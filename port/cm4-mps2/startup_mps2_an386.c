/*
 * Reset and exception handling for the Cortex-M4F on the MPS2 AN386 image
 * (QEMU -machine mps2-an386): the vector table, the reset handler that
 * prepares RAM, the stack paint and the FPU before main, and fault handlers
 * that report through semihosting and end the program with a failure.
 */
#include <stddef.h>
#include <stdint.h>

#include "pdt_port.h"
#include "pdt_port_cm4.h"
#include "pdt_port_common.h"
#include "pdt_port_target.h"

/* Linker-script symbols (mps2_an386.ld). */
extern uint32_t __data_start__[];
extern uint32_t __data_end__[];
extern const uint32_t __data_load__[];
extern uint32_t __bss_start__[];
extern uint32_t __bss_end__[];
extern uint32_t __stack_bottom__[];
extern uint32_t __stack_top__[];

int main(void);

void pdt_cm4_reset_handler(void);
void pdt_cm4_fault_handler(void);
void pdt_cm4_default_handler(void);
void pdt_cm4_systick_handler(void);
void pdt_cm4_fault_report(const uint32_t *frame, uint32_t exc_return);

#define SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)
#define SCB_CFSR  (*(volatile uint32_t *)0xE000ED28u)
#define SCB_HFSR  (*(volatile uint32_t *)0xE000ED2Cu)
#define SCB_MMFAR (*(volatile uint32_t *)0xE000ED34u)
#define SCB_BFAR  (*(volatile uint32_t *)0xE000ED38u)
#define SCB_ICSR  (*(volatile uint32_t *)0xE000ED04u)
#define SCB_SHCSR (*(volatile uint32_t *)0xE000ED24u)
#define SCB_CCR   (*(volatile uint32_t *)0xE000ED14u)

/* ARMv6-M (Cortex-M0/M0+): no FPU, no divide trap, no configurable fault
 * handlers or fault status registers, Thumb-1 only. The same code serves
 * the Cortex-M0 (nRF51), M33 (AN505) and M4F (AN386); the linker script
 * says where memory is. */
#if defined(__ARM_ARCH_6M__)
#define PDT_CM4_ARMV6M 1
#else
#define PDT_CM4_ARMV6M 0
#endif

/* Byte written over the unused stack at reset. */
#define STACK_PAINT 0xC5u

/* Core exceptions 1..15, then the AN386's 32 device interrupts, all of
 * which this port leaves disabled. */
#define VECTOR_COUNT (16u + 32u)

typedef void (*pdt_cm4_vector_t)(void);

__attribute__((section(".vectors"), used)) const pdt_cm4_vector_t pdt_cm4_vectors[VECTOR_COUNT] = {
    (pdt_cm4_vector_t)(uintptr_t)__stack_top__,
    pdt_cm4_reset_handler,
    pdt_cm4_fault_handler, /* NMI */
    pdt_cm4_fault_handler, /* HardFault */
    pdt_cm4_fault_handler, /* MemManage */
    pdt_cm4_fault_handler, /* BusFault */
    pdt_cm4_fault_handler, /* UsageFault */
    0,
    0,
    0,
    0,
    pdt_cm4_default_handler, /* SVCall */
    pdt_cm4_default_handler, /* DebugMonitor */
    0,
    pdt_cm4_default_handler, /* PendSV */
    pdt_cm4_systick_handler,
    /* device interrupts: the rest of the table, filled below */
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
    pdt_cm4_default_handler,
};

void pdt_cm4_reset_handler(void)
{
#if defined(__ARM_FP)
    /* The FPU first: with the hard-float ABI the compiler may use its
     * registers anywhere, and until CP10/CP11 are granted full access any
     * floating-point instruction faults (NOCP). */
    SCB_CPACR |= (0xFu << 20);
    __asm volatile("dsb\n\tisb" ::: "memory");
#endif

#if !PDT_CM4_ARMV6M
    /* Divide by zero traps instead of silently giving 0; unaligned word
     * accesses still work (pdtfit never makes one, newlib might). */
    SCB_CCR |= (1u << 4);
    /* Separate MemManage, BusFault and UsageFault handlers, so a fault
     * shows its own status instead of escalating to HardFault. */
    SCB_SHCSR |= (1u << 16) | (1u << 17) | (1u << 18);
#endif

    pdt_cm4_stack_paint();

    const uint32_t *src = __data_load__;
    for (uint32_t *p = __data_start__; p < __data_end__; p++) {
        *p = *src++;
    }
    for (uint32_t *p = __bss_start__; p < __bss_end__; p++) {
        *p = 0u;
    }

    pdt_port_exit(main());
}

void pdt_cm4_stack_paint(void)
{
    pdt_port_paint_stack((unsigned char *)__stack_bottom__, STACK_PAINT);
}

size_t pdt_cm4_stack_depth(void)
{
    uintptr_t sp;
    __asm volatile("mov %0, sp" : "=r"(sp));
    return (size_t)((uintptr_t)__stack_top__ - sp);
}

size_t pdt_cm4_stack_size(void)
{
    return (size_t)((uintptr_t)__stack_top__ - (uintptr_t)__stack_bottom__);
}

size_t pdt_cm4_stack_used(void)
{
    return pdt_port_painted_used((const unsigned char *)__stack_bottom__,
                                 (const unsigned char *)__stack_top__, STACK_PAINT);
}

/* Reports the fault's status registers and the faulting PC taken from the
 * exception frame, then ends the program with status 3. */
void pdt_cm4_fault_report(const uint32_t *frame, uint32_t exc_return)
{
    uint32_t exception = SCB_ICSR & 0x1FFu;
    static const char msg[] = "\n*** fault: exception";
    pdt_port_write(msg, sizeof msg - 1u);
    pdt_port_write_hex("", exception);
#if !PDT_CM4_ARMV6M
    pdt_port_write_hex("CFSR", SCB_CFSR);
    pdt_port_write_hex("HFSR", SCB_HFSR);
    pdt_port_write_hex("MMFAR", SCB_MMFAR);
    pdt_port_write_hex("BFAR", SCB_BFAR);
#endif
    pdt_port_write_hex("EXC_RETURN", exc_return);
    pdt_port_write_hex("PC", frame[6]);
    pdt_port_write_hex("LR", frame[5]);
    pdt_port_exit(3);
}

/* Picks the stack the exception frame was pushed on and hands it to
 * pdt_cm4_fault_report. */
__attribute__((naked)) void pdt_cm4_fault_handler(void)
{
#if PDT_CM4_ARMV6M
    __asm volatile("movs r0, #4\n\t"
                   "mov r1, lr\n\t"
                   "tst r0, r1\n\t"
                   "bne 1f\n\t"
                   "mrs r0, msp\n\t"
                   "b 2f\n\t"
                   "1: mrs r0, psp\n\t"
                   "2: ldr r2, =pdt_cm4_fault_report\n\t"
                   "bx r2\n\t"
                   ".ltorg\n\t");
#else
    __asm volatile("tst lr, #4\n\t"
                   "ite eq\n\t"
                   "mrseq r0, msp\n\t"
                   "mrsne r0, psp\n\t"
                   "mov r1, lr\n\t"
                   "b pdt_cm4_fault_report\n\t");
#endif
}

void pdt_cm4_default_handler(void)
{
    static const char msg[] = "\n*** unexpected interrupt\n";
    pdt_port_write(msg, sizeof msg - 1u);
    pdt_port_write_hex("exception", SCB_ICSR & 0x1FFu);
    pdt_port_exit(4);
}

/* The target test program's view of the stack (pdt_port_target.h). */
size_t pdt_port_stack_size(void)
{
    return pdt_cm4_stack_size();
}

size_t pdt_port_stack_used(void)
{
    return pdt_cm4_stack_used();
}

void pdt_port_stack_paint(void)
{
    pdt_cm4_stack_paint();
}

size_t pdt_port_stack_depth(void)
{
    return pdt_cm4_stack_depth();
}
