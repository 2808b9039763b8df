/*
 * What the target ports share (port/common: pdt_port_stack.c and
 * pdt_port_report.c): the stack's paint and its high-water mark, and the
 * console's reports of a failed PDT_ASSERT and of a fault. Every target
 * port links it (port/CMakeLists.txt: the Cortex-M, RISC-V and AVR ports);
 * each passes its own stack bounds and pattern. The text goes out by
 * pdt_port_write.
 */
#ifndef PDT_PORT_COMMON_H
#define PDT_PORT_COMMON_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Paints the stack from bottom up to a margin below the caller's frame
 * with the byte pattern. An interrupt taken meanwhile only uses the same
 * free space and leaves it free again. */
void pdt_port_paint_stack(unsigned char *bottom, uint8_t pattern);

/* The deepest use of the stack [bottom, top) since its paint, bytes from
 * top: the lowest byte that no longer holds the pattern. top - bottom
 * means the stack may have overflowed. */
size_t pdt_port_painted_used(const unsigned char *bottom, const unsigned char *top,
                             uint8_t pattern);

/* A NUL-terminated text to the console. */
void pdt_port_write_text(const char *s);

/* "name 0x12345678" and a newline to the console (name at most 16
 * characters). */
void pdt_port_write_hex(const char *name, uint32_t v);

/* "file:line: PDT_ASSERT(expr) failed" and a newline to the console: the
 * report of pdt_port_assert_failed before it ends the program. */
void pdt_port_report_assert(const char *expr, const char *file, int line);

#ifdef __cplusplus
}
#endif

#endif /* PDT_PORT_COMMON_H */
