// Host stand-in for the Arduino core: just what the cadcog sketches use, with a virtual clock.
// Used by tests/bench/test_firmware.py to compile and run the sketches on the host.
#pragma once
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define A0 14
#define A1 15
#define SDA 18  // the Uno's A4
#define SCL 19  // the Uno's A5
#define LOW 0
#define HIGH 1
#define OUTPUT 1
#define DEFAULT 1
#define MSBFIRST 1
#define SPI_MODE0 0

uint32_t micros();
uint32_t millis();
void delay(uint32_t ms);
void delayMicroseconds(uint32_t us);
int analogRead(uint8_t pin);
void analogReference(uint8_t mode);
void pinMode(uint8_t pin, uint8_t mode);
void digitalWrite(uint8_t pin, uint8_t value);

struct HostSerial {
  void begin(uint32_t) {}
  int available();
  int read();
  void println(const char *s) { fputs(s, stdout); fputs("\r\n", stdout); }
};
extern HostSerial Serial;
