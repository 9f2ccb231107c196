// Host stand-in for the Arduino Wire (I2C master) library (see Arduino.h): what the cadcog
// sketches use, with the AVR library's return values (endTransmission: 0 done, 2 address not
// acknowledged; requestFrom: the bytes received, 0 when the address is not acknowledged) and
// its 32-byte buffers. The bus goes to the emulated chip (host_chip.h).
#pragma once
#include "Arduino.h"

struct TwoWire {
  void begin() {}
  void setClock(uint32_t) {}
  void beginTransmission(uint8_t address);
  size_t write(uint8_t b);
  uint8_t endTransmission(bool sendStop = true);
  uint8_t requestFrom(uint8_t address, uint8_t quantity, bool sendStop = true);
  int available();
  int read();

 private:
  uint8_t tx_address_ = 0, tx_[32] = {}, rx_[32] = {};
  size_t tx_len_ = 0, rx_len_ = 0, rx_pos_ = 0;
};
extern TwoWire Wire;
