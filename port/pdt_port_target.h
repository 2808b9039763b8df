/*
 * What the target test program (tests/target) needs from a bare-metal
 * port beyond the port surface (pdt_port.h): the stack's high-water mark
 * and what the tick counter is. Every target port implements it
 * (cm4-mps2 for the Cortex-M cores, rv32-virt for RISC-V); the host port
 * does not.
 */
#ifndef PDT_PORT_TARGET_H
#define PDT_PORT_TARGET_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Bytes reserved for the stack. */
size_t pdt_port_stack_size(void);

/* Deepest stack use since reset or the last pdt_port_stack_paint, bytes
 * from the top of the stack: the free stack is painted with a pattern,
 * this finds the lowest word that changed. A value equal to
 * pdt_port_stack_size means the stack may have overflowed. */
size_t pdt_port_stack_used(void);

/* Paints the free stack below the caller again, so that the next
 * pdt_port_stack_used reports the deepest use from now on. With
 * pdt_port_stack_depth at the call site this measures one function: used
 * after it - depth before it. */
void pdt_port_stack_paint(void);

/* Current stack depth, bytes from the top (the caller's frame included). */
size_t pdt_port_stack_depth(void);

/* The counter behind pdt_port_ticks ("SysTick", "the DWT cycle counter",
 * "mcycle"), or "none" before pdt_port_init. */
const char *pdt_port_counter_name(void);

/* Ticks between two wraps of a counter the port widens by counting its
 * wraps in an interrupt (SysTick), so that a test can cross one; 0 for a
 * counter that needs no such check. */
uint64_t pdt_port_counter_wrap(void);

#ifdef __cplusplus
}
#endif

#endif /* PDT_PORT_TARGET_H */
