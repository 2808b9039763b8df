/*
 * pdtfit's target test program for the ATmega2560 (simavr, see
 * docs/port.md): one line per check on the UART console, ending with
 * "ALL PASSED" or "FAILED", then sleep with interrupts off, where simavr
 * stops. Prints the program's flash and RAM and the stack high-water mark.
 */
#include "pdt/pdt.h"
#include "pdt_port.h"
#include "pdt_port_avr.h"
#include "avr_checks.h"
#include "target_util.h"

avr_arena_t g_avr_arena;

/* The linker's marks (avr-libc's linker scripts): the end of the flash
 * image and of the static RAM, and the start of RAM. */
extern const char __data_load_end;
extern char __data_start;
extern char __heap_start;

void tl_str_flash(tline_t *l, const char *flash_str)
{
    char chunk[17];
    size_t n = 0u;
    char c;
    while ((c = (char)pgm_read_byte(flash_str)) != '\0') {
        flash_str++;
        chunk[n++] = c;
        if (n == sizeof chunk - 1u) {
            chunk[n] = '\0';
            tl_str(l, chunk);
            n = 0u;
        }
    }
    chunk[n] = '\0';
    tl_str(l, chunk);
}

typedef struct avr_check {
    const char *name;
    int (*run)(void); /* returns the number of failed checks */
} avr_check_t;

static const avr_check_t avr_checks[] = {
    {"expm1 and log1p", avr_check_math},
    {"identification", avr_check_ident},
    {"pid", avr_check_pid},
    {"autotune", avr_check_autotune},
};

int main(void)
{
    pdt_port_init();
    tline_t l;
    tl_init(&l);
    TL_STR(&l, "pdtfit ");
    tl_str(&l, PDT_VERSION_STRING);
    TL_STR(&l, " AVR target tests, float build; ticks are CPU cycles at ");
    tl_uint(&l, pdt_port_ticks_per_second());
    TL_STR(&l, " Hz");
    t_info(&l);
    tl_init(&l);
    TL_STR(&l, "avr: flash ");
    tl_uint(&l, pgm_get_far_address(__data_load_end));
    TL_STR(&l, " bytes, static RAM ");
    tl_uint(&l, (uintptr_t)&__heap_start - (uintptr_t)&__data_start);
    TL_STR(&l, " bytes (of which the checks' arena ");
    tl_uint(&l, sizeof g_avr_arena);
    TL_STR(&l, "), stack reserve ");
    tl_uint(&l, pdt_avr_stack_reserve());
    TL_STR(&l, " bytes");
    t_info(&l);

    for (size_t i = 0; i < sizeof avr_checks / sizeof avr_checks[0]; i++) {
        tl_init(&l);
        TL_STR(&l, "-- ");
        tl_str(&l, avr_checks[i].name);
        tl_emit(&l);
        (void)avr_checks[i].run();
    }

    size_t stack = t_stack_max();
    tl_init(&l);
    TL_STR(&l, "stack high-water mark of the program ");
    tl_uint(&l, stack);
    TL_STR(&l, " of ");
    tl_uint(&l, pdt_avr_stack_reserve());
    TL_STR(&l, " bytes");
    t_info(&l);
    /* The whole reserve used means the stack ran into .bss. */
    if (!(stack < pdt_avr_stack_reserve())) {
        tl_init(&l);
        TL_STR(&l, "stack within its reserve");
        (void)t_verdict(false, &l);
    }

    tl_init(&l);
    tl_uint(&l, t_checks_run());
    TL_STR(&l, " checks, ");
    tl_uint(&l, t_checks_failed());
    TL_STR(&l, " failed: ");
    tl_str(&l, t_checks_failed() == 0u ? "ALL PASSED" : "FAILED");
    tl_emit(&l);
    pdt_port_exit(t_checks_failed() == 0u ? 0 : 1);
    return 0;
}
