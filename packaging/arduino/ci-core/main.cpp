// The Arduino core's main for the compile check: setup once, loop a while.
#include "Arduino.h"

CiSerial Serial;

void delay(unsigned long ms)
{
    (void)ms;
}

int main()
{
    setup();
    for (int i = 0; i < 2000; i++) {
        loop();
    }
    return 0;
}
