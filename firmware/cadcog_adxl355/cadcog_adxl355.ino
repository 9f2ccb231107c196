/* cadcog: an Analog Devices ADXL355 three-axis MEMS accelerometer on SPI, streamed in the cadcog
 * line protocol (docs/bench.md) as raw 20-bit counts of x, y and z (value=accel; at the +-2 g
 * range, acceleration = raw / 256000 g).
 *
 * Wiring (docs/bench.md has the table): the ADXL355 is a 3.3 V part (supply 2.25-3.6 V; its
 * logic pins must never see 5 V): VDD and VDDIO from the Uno's 3.3 V pin, a level shifter from
 * the 5 V Uno to the sensor on SCLK, MOSI and CS; MISO -> MISO; SCLK -> SCK, MOSI -> MOSI,
 * CS -> PIN_CS, GND -> GND. A 3.3 V board needs no shifter.
 *
 * The chip (ADXL354/ADXL355 data sheet, Analog Devices, register map; the figures below were
 * checked against drivers that quote it: ADI's no-OS adxl355.h, the Linux IIO adxl355_core.c and
 * Zephyr's ADXL355 bindings): SPI mode 0, at most 10 MHz; a transaction starts with the command
 * byte (address << 1) | R (R = 1: read), then reads or writes consecutive registers.
 * DEVID_AD 0x00 = 0xAD, DEVID_MST 0x01 = 0x1D, PARTID 0x02 = 0xED; STATUS 0x04 (bit 0
 * DATA_RDY); XDATA3..ZDATA1 0x08..0x10: per axis a 20-bit two's complement value, left-justified
 * in three bytes (bits 19:12, 11:4, then bits 3:0 in bits 7:4 of the third byte, whose bits 3:0
 * are reserved); FILTER 0x28 (bits 6:4 high-pass corner, 0 = off; bits 3:0 ODR_LPF: output rate
 * 4000 / 2^n Hz, low-pass corner a quarter of it); RANGE 0x2C (bits 1:0: 01 +-2 g, 10 +-4 g,
 * 11 +-8 g; 256000, 128000, 64000 LSB/g: 3.9, 7.8, 15.6 ug/LSB; bits 7:6 I2C speed and interrupt
 * polarity, kept); POWER_CTL 0x2D (bit 0 standby, set at power-on); RESET 0x2F (0x52: as at
 * power-on).
 *
 * Start-up: reset, check the three ID registers, then in standby set the filter (high-pass off,
 * 31.25 Hz output rate, low-pass corner 7.8 Hz: below the 10 Hz Nyquist limit of the 20 Hz
 * samples) and the +-2 g range, start measuring, and read the three registers back. A chip that
 * fails sends a header with sensor=ADXL355-FAULT and no samples. Then every PERIOD_US: one burst
 * from DEVID_AD to ZDATA1 (the three axes of one conversion, with the ID and STATUS), one
 * sample line with x, y, z sign-extended to 32 bits; status bit 0 = DEVID_AD reads wrong (the
 * chip does not answer), bit 1 = no new conversion since the last sample (the chip has fallen
 * back to standby, e.g. after a brown-out of the sensor: the sketch configures it again). The
 * host drops flagged samples. The header goes out at start, every HEADER_EVERY samples, and
 * when the host sends '?'.
 */
#include <SPI.h>

#include "cadcog_protocol.h"

static const uint8_t PIN_CS = 10;
static const uint32_t BAUD = 115200;
static const uint32_t RATE_HZ = 20;
static const char RATE_TEXT[] = "20";
static const uint16_t HEADER_EVERY = 40; /* samples: every 2 s at 20 Hz */
static const uint32_t PERIOD_US = 1000000UL / RATE_HZ;
static const SPISettings ADXL_SPI(1000000, MSBFIRST, SPI_MODE0); /* slow enough for shifters */

static const uint8_t REG_DEVID_AD = 0x00;
static const uint8_t REG_DEVID_MST = 0x01;
static const uint8_t REG_PARTID = 0x02;
static const uint8_t REG_STATUS = 0x04;
static const uint8_t REG_XDATA3 = 0x08;
static const uint8_t REG_FILTER = 0x28;
static const uint8_t REG_RANGE = 0x2C;
static const uint8_t REG_POWER_CTL = 0x2D;
static const uint8_t REG_RESET = 0x2F;
static const uint8_t DEVID_AD = 0xAD;
static const uint8_t DEVID_MST = 0x1D;
static const uint8_t PARTID = 0xED;
static const uint8_t RESET_CODE = 0x52;
static const uint8_t STATUS_DATA_RDY = 0x01;
static const uint8_t POWER_STANDBY = 0x01;
static const uint8_t POWER_MEASURE = 0x00; /* temperature on, DRDY pin on (unused) */

/* The configuration, and what the header says of it (keep them together). */
static const uint8_t FILTER_VALUE = 0x07;      /* high-pass off; ODR 31.25 Hz, low-pass 7.8 Hz */
static const uint8_t RANGE_BITS = 0x01;        /* +-2 g: 256000 LSB/g */
static const char LSB_G_TEXT[] = "3.90625e-06"; /* 1 / 256000 g */
static const char FULL_SCALE_G_TEXT[] = "2";

static uint32_t next_us;
static uint32_t seq;
static uint16_t since_header;
static bool sensor_ok;

static void read_registers(uint8_t first, uint8_t *out, uint8_t n) {
  SPI.beginTransaction(ADXL_SPI);
  digitalWrite(PIN_CS, LOW);
  SPI.transfer((uint8_t)((first << 1) | 0x01));
  for (uint8_t i = 0; i < n; i++) out[i] = SPI.transfer(0x00);
  digitalWrite(PIN_CS, HIGH);
  SPI.endTransaction();
}

static uint8_t read_register(uint8_t address) {
  uint8_t value;
  read_registers(address, &value, 1);
  return value;
}

static void write_register(uint8_t address, uint8_t value) {
  SPI.beginTransaction(ADXL_SPI);
  digitalWrite(PIN_CS, LOW);
  SPI.transfer((uint8_t)(address << 1));
  SPI.transfer(value);
  digitalWrite(PIN_CS, HIGH);
  SPI.endTransaction();
}

/* Filter and range (written in standby), then measure; true if the registers read back so. */
static bool configure() {
  write_register(REG_POWER_CTL, POWER_STANDBY);
  write_register(REG_FILTER, FILTER_VALUE);
  uint8_t range = (uint8_t)((read_register(REG_RANGE) & 0xFC) | RANGE_BITS);
  write_register(REG_RANGE, range);
  write_register(REG_POWER_CTL, POWER_MEASURE);
  return read_register(REG_FILTER) == FILTER_VALUE && read_register(REG_RANGE) == range &&
         read_register(REG_POWER_CTL) == POWER_MEASURE;
}

static bool start_sensor() {
  write_register(REG_RESET, RESET_CODE);
  delay(10);
  uint8_t id[3];
  read_registers(REG_DEVID_AD, id, sizeof id);
  if (id[REG_DEVID_AD] != DEVID_AD || id[REG_DEVID_MST] != DEVID_MST || id[REG_PARTID] != PARTID)
    return false;
  if (!configure()) return false;
  delay(100); /* the first conversions, through the low-pass filter */
  return true;
}

/* A 20-bit two's complement value, left-justified in three bytes, as a 32-bit integer. */
static int32_t axis(const uint8_t *b) {
  uint32_t raw = ((uint32_t)b[0] << 12) | ((uint32_t)b[1] << 4) | ((uint32_t)b[2] >> 4);
  if (raw & 0x80000UL) raw |= 0xFFF00000UL;
  return (int32_t)raw;
}

static void send_header() {
  char buf[CADCOG_LINE_MAX];
  if (cadcog_format_header_accel(buf, sizeof buf, "arduino",
                                 sensor_ok ? "ADXL355" : "ADXL355-FAULT", RATE_TEXT, LSB_G_TEXT,
                                 FULL_SCALE_G_TEXT))
    Serial.println(buf);
  since_header = 0;
}

void setup() {
  Serial.begin(BAUD);
  pinMode(PIN_CS, OUTPUT);
  digitalWrite(PIN_CS, HIGH);
  SPI.begin();
  sensor_ok = start_sensor();
  send_header();
  next_us = micros();
}

void loop() {
  while (Serial.available() > 0) {
    if (Serial.read() == '?') send_header();
  }
  if (!sensor_ok) return;
  uint32_t now = micros();
  if ((int32_t)(now - next_us) < 0) return;
  if (now - next_us > 4 * PERIOD_US) next_us = now;
  next_us += PERIOD_US;
  uint32_t t_ms = millis();
  uint8_t r[REG_XDATA3 + 9]; /* DEVID_AD .. ZDATA1 */
  read_registers(REG_DEVID_AD, r, sizeof r);
  uint8_t status = 0;
  if (r[REG_DEVID_AD] != DEVID_AD) status |= 1;
  else if (!(r[REG_STATUS] & STATUS_DATA_RDY)) status |= 2;
  seq++;
  char buf[CADCOG_LINE_MAX];
  if (cadcog_format_sample3(buf, sizeof buf, seq, t_ms, axis(r + REG_XDATA3),
                            axis(r + REG_XDATA3 + 3), axis(r + REG_XDATA3 + 6), status))
    Serial.println(buf);
  if (status & 2) configure();
  if (++since_header >= HEADER_EVERY) send_header();
}
