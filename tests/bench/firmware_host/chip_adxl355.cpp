// Emulated Analog Devices ADXL355 on SPI (chip select on pin 10, SPI mode 0), from the register
// map of its data sheet (ADXL354/ADXL355): a transaction's first byte is (address << 1) | R,
// R = 1 to read; the following bytes read or write consecutive registers.
//
// - power-on state: DEVID_AD 0xAD, DEVID_MST 0x1D, PARTID 0xED, REVID 0x01, FIFO_SAMPLES 0x60,
//   RANGE 0x81 (+-2 g), POWER_CTL 0x01 (standby); 0x52 written to RESET restores it;
// - registers below 0x1E are read-only;
// - measuring (POWER_CTL bit 0 clear), it converts at the ODR of FILTER bits 3:0 (4000 / 2^n Hz);
//   STATUS bit 0 (DATA_RDY) says a conversion happened since STATUS was last read (reading it
//   clears it);
// - each burst that reads XDATA3 while measuring latches the test's next x, y, z counts
//   (host_next_xyz) into XDATA3..ZDATA1: 20-bit two's complement, left-justified (bits 19:12,
//   11:4, then 3:0 in bits 7:4 of the third byte). The reserved bits 3:0 of XDATA1, YDATA1 and
//   ZDATA1 read 0b1010, to show that a sketch discards them. In standby the data stay as they
//   were (zero after a reset).
//
// Options: --id=0xNN reads another PARTID (0xE9: an ADXL359); --reset-at-ms=T resets the chip
// once at the first transaction after T ms (a brown-out of the sensor alone). Each transaction's
// MOSI bytes go to stderr ("SPI 5E52"), and at the end the configuration registers
// ("REG 2C 81").
#include <stdio.h>
#include <stdlib.h>

#include "Arduino.h"
#include "host_chip.h"

static const uint8_t PIN_CS = 10;
static uint8_t reg[0x30];
static uint8_t part_id = 0xED;
static uint64_t reset_at_us = 0;
static bool selected = false;
static int byte_index = 0;
static uint8_t address = 0;
static bool reading = false;
static uint64_t measuring_since_us = 0, conversions_seen = 0;
static char frame_text[3 * 64];
static size_t frame_len = 0;

static void power_on_state() {
  memset(reg, 0, sizeof reg);
  reg[0x00] = 0xAD;
  reg[0x01] = 0x1D;
  reg[0x02] = part_id;
  reg[0x03] = 0x01;
  reg[0x29] = 0x60;
  reg[0x2C] = 0x81;
  reg[0x2D] = 0x01;
}
static bool measuring() { return !(reg[0x2D] & 0x01); }
static uint64_t conversions() {
  if (!measuring()) return 0;
  uint8_t code = reg[0x28] & 0x0F;
  if (code > 10) code = 10;
  double odr_hz = 4000.0 / (double)(1u << code);
  return (uint64_t)((double)(host_now_us() - measuring_since_us) * odr_hz / 1e6);
}

static uint8_t read_register(uint8_t a) {
  if (a >= sizeof reg) return 0;
  if (a == 0x04) {
    uint64_t c = conversions();
    uint8_t ready = c > conversions_seen ? 0x01 : 0x00;
    conversions_seen = c;
    return (uint8_t)(reg[0x04] | ready);
  }
  if (a == 0x08 && measuring()) {
    int32_t xyz[3];
    host_next_xyz(xyz);
    for (int i = 0; i < 3; i++) {
      uint32_t v = (uint32_t)xyz[i] & 0xFFFFFu;
      reg[0x08 + 3 * i] = (uint8_t)(v >> 12);
      reg[0x09 + 3 * i] = (uint8_t)(v >> 4);
      reg[0x0A + 3 * i] = (uint8_t)(((v & 0x0F) << 4) | 0x0A);
    }
  }
  return reg[a];
}

static void write_register(uint8_t a, uint8_t v) {
  if (a < 0x1E || a >= sizeof reg) return;  // read-only or beyond the map
  if (a == 0x2F) {
    if (v == 0x52) power_on_state();
    return;
  }
  bool was_measuring = measuring();
  reg[a] = v;
  if (a == 0x2D && !was_measuring && measuring()) {
    measuring_since_us = host_now_us();
    conversions_seen = 0;
  }
}

void chip_start() {
  const char *id = host_option("id");
  if (id) part_id = (uint8_t)strtoul(id, nullptr, 0);
  const char *at = host_option("reset-at-ms");
  if (at) reset_at_us = 1000ull * strtoull(at, nullptr, 0);
  power_on_state();
}
void chip_pin(uint8_t pin, uint8_t value) {
  if (pin != PIN_CS) return;
  if (value == LOW && !selected) {
    if (reset_at_us && host_now_us() >= reset_at_us) {
      fprintf(stderr, "RESET %lu ms\n", (unsigned long)(host_now_us() / 1000));
      power_on_state();
      reset_at_us = 0;
    }
    selected = true;
    byte_index = 0;
    frame_len = 0;
  } else if (value == HIGH && selected) {
    selected = false;
    frame_text[frame_len] = '\0';
    fprintf(stderr, "SPI %s\n", frame_text);
  }
}
uint8_t chip_spi_transfer(uint8_t mosi) {
  host_advance_us(8);  // 1 MHz
  if (!selected) return 0xFF;
  if (frame_len + 3 < sizeof frame_text)
    frame_len += (size_t)snprintf(frame_text + frame_len, 3, "%02X", mosi);
  if (byte_index++ == 0) {
    address = (uint8_t)(mosi >> 1);
    reading = mosi & 0x01;
    return 0x00;
  }
  uint8_t a = address++;
  if (reading) return read_register(a);
  write_register(a, mosi);
  return 0x00;
}
bool chip_i2c_write(uint8_t, const uint8_t *, size_t) { return false; }
bool chip_i2c_read(uint8_t, uint8_t *, size_t) { return false; }
void chip_finish() {
  static const uint8_t shown[] = {0x28, 0x2C, 0x2D};
  for (uint8_t a : shown) fprintf(stderr, "REG %02X %02X\n", a, reg[a]);
}
