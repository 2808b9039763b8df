/*
 * The target ports' shared console reports (pdt_port_common.h): a text, a
 * register in hex, a failed PDT_ASSERT. A file of its own, so that a
 * program that reports nothing (the AVR's: its strings would take RAM)
 * links none of it.
 */
#include "pdt_port_common.h"

#include "pdt_port.h"

void pdt_port_write_text(const char *s)
{
    size_t n = 0;
    while (s[n] != '\0') {
        n++;
    }
    pdt_port_write(s, n);
}

void pdt_port_write_hex(const char *name, uint32_t v)
{
    static const char digits[] = "0123456789abcdef";
    char buf[32];
    size_t n = 0;
    while (name[n] != '\0' && n < 16u) {
        buf[n] = name[n];
        n++;
    }
    buf[n++] = ' ';
    buf[n++] = '0';
    buf[n++] = 'x';
    for (unsigned i = 0; i < 8u; i++) {
        buf[n++] = digits[(v >> (28u - 4u * i)) & 0xFu];
    }
    buf[n++] = '\n';
    pdt_port_write(buf, n);
}

void pdt_port_report_assert(const char *expr, const char *file, int line)
{
    char num[10];
    size_t n = sizeof num;
    uint32_t v = line < 0 ? 0u : (uint32_t)line;
    do {
        num[--n] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0u && n > 0u);
    pdt_port_write_text(file);
    pdt_port_write_text(":");
    pdt_port_write(num + n, sizeof num - n);
    pdt_port_write_text(": PDT_ASSERT(");
    pdt_port_write_text(expr);
    pdt_port_write_text(") failed\n");
}
