// Emulated InvenSense MPU-6050 on I2C at 0x68 (AD0 low, as on the GY-521), from its register map
// (RM-MPU-6000A-00): a write's first byte sets the register pointer, the following bytes write
// consecutive registers; a read returns consecutive registers from the pointer.
//
// - power-on state: every register 0x00 but PWR_MGMT_1 0x40 (SLEEP) and WHO_AM_I 0x68; a write
//   with PWR_MGMT_1 bit 7 (DEVICE_RESET) restores it;
// - read-only: INT_STATUS 0x3A, the measurements 0x3B..0x60, WHO_AM_I 0x75;
// - awake (SLEEP clear), it samples at 1 kHz / (1 + SMPLRT_DIV) with the DLPF on (DLPF_CFG 1-6
//   in CONFIG), 8 kHz / (1 + SMPLRT_DIV) with it off; INT_STATUS bit 0 (DATA_RDY_INT) says a
//   sample was taken since INT_STATUS was last read, if INT_ENABLE bit 0 (DATA_RDY_EN) is set
//   (reading clears it: INT_RD_CLEAR = 0);
// - each read that covers ACCEL_XOUT_H while awake latches the test's next x, y, z counts
//   (host_next_xyz) into ACCEL_XOUT_H..ACCEL_ZOUT_L: 16-bit two's complement, big-endian. Asleep,
//   the measurements stay as they were (zero after a reset).
//
// Options: --id=0xNN reads another WHO_AM_I (0x70: an MPU-6500 sold as a GY-521); --absent=1: no
// device acknowledges; --reset-at-ms=T resets the chip once at the first transaction after T ms
// (a brown-out of the sensor alone). At the end the configuration registers go to stderr
// ("REG 1C 00"). No device on SPI.
#include <stdio.h>
#include <stdlib.h>

#include "Arduino.h"
#include "host_chip.h"

static const uint8_t ADDRESS = 0x68;
static uint8_t reg[0x80];
static uint8_t who_am_i = 0x68;
static bool absent = false;
static uint64_t reset_at_us = 0;
static uint8_t pointer = 0;
static uint64_t awake_since_us = 0, samples_seen = 0;

static void power_on_state() {
  memset(reg, 0, sizeof reg);
  reg[0x6B] = 0x40;
  reg[0x75] = who_am_i;
}
static bool awake() { return !(reg[0x6B] & 0x40); }
static uint64_t samples() {
  if (!awake()) return 0;
  uint8_t dlpf = reg[0x1A] & 0x07;
  double rate_hz = (dlpf == 0 || dlpf == 7 ? 8000.0 : 1000.0) / (1.0 + reg[0x19]);
  return (uint64_t)((double)(host_now_us() - awake_since_us) * rate_hz / 1e6);
}

static uint8_t read_register(uint8_t a) {
  a &= 0x7F;
  if (a == 0x3A) {
    uint64_t s = samples();
    uint8_t ready = (reg[0x38] & 0x01) && s > samples_seen ? 0x01 : 0x00;
    samples_seen = s;
    return ready;
  }
  if (a == 0x3B && awake()) {
    int32_t xyz[3];
    host_next_xyz(xyz);
    for (int i = 0; i < 3; i++) {
      uint16_t v = (uint16_t)xyz[i];
      reg[0x3B + 2 * i] = (uint8_t)(v >> 8);
      reg[0x3C + 2 * i] = (uint8_t)v;
    }
  }
  return reg[a];
}

static void write_register(uint8_t a, uint8_t v) {
  a &= 0x7F;
  if (a == 0x3A || (a >= 0x3B && a <= 0x60) || a == 0x75) return;  // read-only
  if (a == 0x6B && (v & 0x80)) {
    power_on_state();
    return;
  }
  bool was_awake = awake();
  reg[a] = v;
  if (a == 0x6B && !was_awake && awake()) {
    awake_since_us = host_now_us();
    samples_seen = 0;
  }
}

static bool acknowledges(uint8_t address) {
  if (reset_at_us && host_now_us() >= reset_at_us) {
    fprintf(stderr, "RESET %lu ms\n", (unsigned long)(host_now_us() / 1000));
    power_on_state();
    reset_at_us = 0;
  }
  return !absent && address == ADDRESS;
}

void chip_start() {
  const char *id = host_option("id");
  if (id) who_am_i = (uint8_t)strtoul(id, nullptr, 0);
  absent = host_option("absent") != nullptr;
  const char *at = host_option("reset-at-ms");
  if (at) reset_at_us = 1000ull * strtoull(at, nullptr, 0);
  power_on_state();
}
void chip_pin(uint8_t, uint8_t) {}
uint8_t chip_spi_transfer(uint8_t) { return 0xFF; }
bool chip_i2c_write(uint8_t address, const uint8_t *data, size_t n) {
  if (!acknowledges(address)) return false;
  if (n == 0) return true;
  pointer = data[0];
  for (size_t i = 1; i < n; i++) write_register(pointer++, data[i]);
  return true;
}
bool chip_i2c_read(uint8_t address, uint8_t *data, size_t n) {
  if (!acknowledges(address)) return false;
  for (size_t i = 0; i < n; i++) data[i] = read_register(pointer++);
  return true;
}
void chip_finish() {
  static const uint8_t shown[] = {0x19, 0x1A, 0x1C, 0x38, 0x6B};
  for (uint8_t a : shown) fprintf(stderr, "REG %02X %02X\n", a, reg[a]);
}
