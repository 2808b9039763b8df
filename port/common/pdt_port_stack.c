/*
 * The target ports' shared stack paint and high-water mark
 * (pdt_port_common.h). Nothing here touches a register or a global: the
 * paint runs in the reset handlers too, before .data and .bss are set up.
 */
#include "pdt_port_common.h"

/* Bytes left unpainted below this function's own frame: the locals the
 * compiler places below the marker, and the frame of nothing called. */
#define PAINT_MARGIN 64u

void pdt_port_paint_stack(unsigned char *bottom, uint8_t pattern)
{
    /* Everything below this frame is free; the marker's address stands
     * for the stack pointer, less a margin. Written through a volatile
     * pointer, so that the loop stays a loop and calls no memset, whose
     * frame would lie in the painted part. */
    volatile unsigned char marker = 0u;
    const uintptr_t here = (uintptr_t)&marker;
    const uintptr_t from = (uintptr_t)bottom;
    if (here < from + PAINT_MARGIN) {
        return;
    }
    volatile unsigned char *p = bottom;
    for (uintptr_t left = here - PAINT_MARGIN - from; left > 0u; left--) {
        *p = pattern;
        p++;
    }
}

size_t pdt_port_painted_used(const unsigned char *bottom, const unsigned char *top, uint8_t pattern)
{
    const volatile unsigned char *p = bottom;
    while (p < top && *p == pattern) {
        p++;
    }
    return (size_t)((uintptr_t)top - (uintptr_t)p);
}
