/*
 * The AVR port: USART0 as the console (simavr prints what it sends),
 * Timer1 at the CPU clock with an overflow count as the tick counter (one
 * tick a cycle), and the end of the run as sleep with interrupts off,
 * which simavr takes as the end of the program. On an Arduino Mega the
 * same code prints on the USB serial port (at 1 Mbaud) and stops.
 */
#include "pdt_port.h"
#include "pdt_port_avr.h"
#include "pdt_port_common.h"

#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>

#ifndef F_CPU
#error "F_CPU (the CPU clock in Hz) must be defined, as cmake/avr-atmega2560.cmake does"
#endif

#define STACK_PAINT 0xA5u

/* Timer1 overflows, each 2^16 cycles. Written by the interrupt only. */
static volatile uint32_t g_overflows;

/* The linker's end of .bss, where the free RAM begins. */
extern uint8_t __heap_start;

ISR(TIMER1_OVF_vect)
{
    g_overflows++;
}

void pdt_port_init(void)
{
    static uint8_t done;
    if (done != 0u) {
        return;
    }
    done = 1u;
    /* 1 Mbaud at 16 MHz with the doubled rate (UBRR = 1). */
    UCSR0A = (uint8_t)(1u << U2X0);
    UBRR0 = (uint16_t)(F_CPU / 8u / 1000000u - 1u);
    UCSR0B = (uint8_t)(1u << TXEN0);
    UCSR0C = (uint8_t)((1u << UCSZ01) | (1u << UCSZ00));
    TCCR1A = 0u;
    TCCR1B = (uint8_t)(1u << CS10); /* no prescaler: one tick a cycle */
    TIMSK1 = (uint8_t)(1u << TOIE1);
    pdt_avr_stack_paint();
    sei();
}

void pdt_port_write(const char *text, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        while ((UCSR0A & (1u << UDRE0)) == 0u) {
        }
        UDR0 = (uint8_t)text[i];
    }
}

uint64_t pdt_port_ticks(void)
{
    uint8_t sreg = SREG;
    cli();
    uint16_t low = TCNT1;
    uint32_t high = g_overflows;
    /* An overflow pending and not yet counted belongs to this reading when
     * the count already wrapped. */
    if ((TIFR1 & (1u << TOV1)) != 0u && low < 0x8000u) {
        high++;
    }
    SREG = sreg;
    return ((uint64_t)high << 16) | low;
}

uint64_t pdt_port_ticks_per_second(void)
{
    return F_CPU;
}

void pdt_port_assert_failed(const char *expr, const char *file, int line)
{
    static const char msg[] = "assertion failed\n";
    (void)expr;
    (void)file;
    (void)line;
    pdt_port_write(msg, sizeof msg - 1u);
    pdt_port_exit(1);
}

void pdt_port_exit(int status)
{
    (void)status; /* the console's last line carries the verdict */
    /* Let the last byte leave the UART, then sleep with interrupts off:
     * simavr ends the run there. */
    while ((UCSR0A & (1u << UDRE0)) == 0u) {
    }
    for (volatile uint16_t i = 0; i < 1000u; i++) {
    }
    cli();
    /* Power-down, enabled (avr-libc's set_sleep_mode is an int
     * expression -Wconversion refuses). */
    SMCR = (uint8_t)((1u << SM1) | (1u << SE));
    for (;;) {
        sleep_cpu();
    }
}

size_t pdt_avr_stack_reserve(void)
{
    return (size_t)(RAMEND + 1u - (uintptr_t)&__heap_start);
}

size_t pdt_avr_stack_depth(void)
{
    return (size_t)(RAMEND - SP);
}

void pdt_avr_stack_paint(void)
{
    pdt_port_paint_stack(&__heap_start, STACK_PAINT);
}

size_t pdt_avr_stack_used(void)
{
    return pdt_port_painted_used(&__heap_start, (const uint8_t *)(uintptr_t)(RAMEND + 1u),
                                 STACK_PAINT);
}
