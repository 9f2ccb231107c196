// Emulated Murata SCL3300 on SPI (chip select on pin 10): it answers each frame during the next
// one (off-frame protocol), with its own CRC (table-driven, independent of the sketch's);
// ANG_X of read k is -8000 + 3 k, ANG_Y is 12000 - 5 k. Every request's CRC is checked; the
// commands go to stderr ("SPI %08X"). No device on I2C.
#include <stdio.h>

#include "Arduino.h"
#include "host_chip.h"

static uint8_t crc_table[256];
static uint8_t emu_crc(uint32_t frame) {
  if (!crc_table[1]) {
    for (int i = 0; i < 256; i++) {
      uint8_t c = (uint8_t)i;
      for (int b = 0; b < 8; b++) c = (c & 0x80) ? (uint8_t)((c << 1) ^ 0x1D) : (uint8_t)(c << 1);
      crc_table[i] = c;
    }
  }
  uint8_t c = 0xFF;
  for (int shift = 24; shift >= 8; shift -= 8) c = crc_table[c ^ (uint8_t)(frame >> shift)];
  return (uint8_t)~c;
}
static uint32_t pending = 0, request = 0, out_frame = 0;
static int byte_index = 0;
static uint32_t reads_x, reads_y;

static uint32_t respond(uint32_t req) {
  uint8_t rs = emu_crc(req) == (uint8_t)(req & 0xFF) ? 1 : 3;
  uint32_t op = req >> 24;  // R/W bit and address, as sent
  uint16_t data = 0;
  if (op == 0x24) data = (uint16_t)(int16_t)(-8000 + 3 * (int32_t)reads_x++);
  else if (op == 0x28) data = (uint16_t)(int16_t)(12000 - 5 * (int32_t)reads_y++);
  else if (op == 0x40) data = 0x00C1;
  else if (op & 0x80) data = (uint16_t)((req >> 8) & 0xFFFF);  // a write echoes its data
  uint32_t f = (op << 24) | ((uint32_t)rs << 24) | ((uint32_t)data << 8);
  return f | emu_crc(f);
}

void chip_start() {}
void chip_pin(uint8_t pin, uint8_t value) {
  if (pin != 10) return;
  if (value == LOW) {
    out_frame = pending;
    request = 0;
    byte_index = 0;
  } else {
    fprintf(stderr, "SPI %08lX\n", (unsigned long)request);
    pending = respond(request);
  }
}
uint8_t chip_spi_transfer(uint8_t b) {
  request = (request << 8) | b;
  uint8_t out = (uint8_t)(out_frame >> (24 - 8 * byte_index));
  byte_index++;
  host_advance_us(4);
  return out;
}
bool chip_i2c_write(uint8_t, const uint8_t *, size_t) { return false; }
bool chip_i2c_read(uint8_t, uint8_t *, size_t) { return false; }
void chip_finish() {}
