// The Arduino core's main for the compile check: setup once, loop a while.
#include "Arduino.h"

CiSerial Serial;

void delay(unsigned long ms)
{
    (void)ms;
}

#if defined(__AVR__)
#include <avr/io.h>
#include <stdlib.h>

void CiSerial::begin(unsigned long baud)
{
    (void)baud;
    UCSR0A = (uint8_t)(1u << U2X0);
    UBRR0 = 1u; /* 1 Mbaud at 16 MHz */
    UCSR0B = (uint8_t)(1u << TXEN0);
}

void CiSerial::print(const char *s)
{
    for (; *s != '\0'; s++) {
        while ((UCSR0A & (1u << UDRE0)) == 0u) {
        }
        UDR0 = (uint8_t)*s;
    }
}

void CiSerial::println(const char *s)
{
    print(s);
    print("\n");
}

void CiSerial::println(double v)
{
    char buf[16];
    println(dtostrf(v, 1, 4, buf));
}
#endif

int main()
{
    setup();
    for (int i = 0; i < 2000; i++) {
        loop();
    }
#if defined(__AVR__)
    /* simavr ends the run at a sleep with interrupts off. */
    Serial.println("ci-core: end");
    for (volatile uint16_t i = 0; i < 2000u; i++) {
    }
    __asm__ __volatile__("cli");
    SMCR = (uint8_t)((1u << SM1) | (1u << SE));
    for (;;) {
        __asm__ __volatile__("sleep");
    }
#endif
    return 0;
}
