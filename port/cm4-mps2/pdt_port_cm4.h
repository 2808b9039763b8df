/*
 * What the Cortex-M4F MPS2 AN386 port offers beyond the port surface
 * (pdt_port.h): the stack high-water mark and the clock the tick counter
 * runs at.
 */
#ifndef PDT_PORT_CM4_H
#define PDT_PORT_CM4_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The core clock, Hz; the tick counter counts it. 25 MHz on the AN386
 * image; the build sets it for the other boards this port serves
 * (port/CMakeLists.txt: 20 MHz on the AN505, 16 MHz on the nRF51). */
#ifndef PDT_CM4_CORE_HZ
#define PDT_CM4_CORE_HZ 25000000u
#endif

/* Where pdt_port_ticks comes from. */
typedef enum pdt_cm4_counter {
    PDT_CM4_COUNTER_NONE = 0,   /* pdt_port_init not called yet */
    PDT_CM4_COUNTER_DWT = 1,    /* DWT->CYCCNT, widened to 64 bits */
    PDT_CM4_COUNTER_SYSTICK = 2 /* SysTick on the core clock, with a wrap count */
} pdt_cm4_counter_t;

/* The counter pdt_port_init chose: the DWT cycle counter when it counts
 * (real silicon), else SysTick (QEMU, which does not model the DWT). */
pdt_cm4_counter_t pdt_cm4_counter(void);

/* Bytes reserved for the stack (the linker script's PDT_STACK_SIZE). */
size_t pdt_cm4_stack_size(void);

/* Deepest stack use since reset or the last pdt_cm4_stack_paint, bytes
 * from the top of the stack: the free stack is painted with a pattern, this
 * finds the lowest word that changed. A value equal to pdt_cm4_stack_size
 * means the stack may have overflowed. */
size_t pdt_cm4_stack_used(void);

/* Paints the free stack below the caller again (the reset handler does it
 * once), so that the next pdt_cm4_stack_used reports the deepest use from
 * now on. With pdt_cm4_stack_depth at the call site this measures one
 * function: used after it - depth before it. */
void pdt_cm4_stack_paint(void);

/* Current stack depth, bytes from the top (the caller's frame included). */
size_t pdt_cm4_stack_depth(void);

#ifdef __cplusplus
}
#endif

#endif /* PDT_PORT_CM4_H */
