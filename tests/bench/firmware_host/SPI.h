// Host stand-in for the Arduino SPI library (see Arduino.h).
#pragma once
#include "Arduino.h"

struct SPISettings {
  SPISettings(uint32_t, uint8_t, uint8_t) {}
};
struct HostSPI {
  void begin() {}
  void beginTransaction(const SPISettings &) {}
  void endTransaction() {}
  uint8_t transfer(uint8_t b);
};
extern HostSPI SPI;
