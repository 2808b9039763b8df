/*
 * What the AVR port (ATmega2560 under simavr, or on an Arduino Mega) offers
 * beyond the port surface (pdt_port.h): the stack high-water mark and the
 * free RAM, which bound what fits in 8 KiB.
 */
#ifndef PDT_PORT_AVR_H
#define PDT_PORT_AVR_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Bytes from the end of .bss (__heap_start) to the top of RAM: the stack's
 * whole reserve (there is no heap). */
size_t pdt_avr_stack_reserve(void);

/* Deepest stack use since pdt_port_init or the last pdt_avr_stack_paint, bytes
 * from the top of RAM: the free RAM is painted with a pattern and this
 * finds the lowest byte that changed. */
size_t pdt_avr_stack_used(void);

/* Paints the free RAM below the caller again, so that the next
 * pdt_avr_stack_used reports the deepest use from now on. */
void pdt_avr_stack_paint(void);

/* Current stack depth, bytes from the top of RAM. */
size_t pdt_avr_stack_depth(void);

#ifdef __cplusplus
}
#endif

#endif /* PDT_PORT_AVR_H */
