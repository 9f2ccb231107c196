/* cadcog: an InvenSense MPU-6050 (the GY-521 board) on I2C, streamed in the cadcog line protocol
 * (docs/bench.md) as raw 16-bit counts of its accelerometer's x, y and z (value=accel; at the
 * +-2 g range, acceleration = raw / 16384 g). The gyroscope is not used.
 *
 * Wiring (docs/bench.md has the table): GY-521 VCC -> 5 V (its regulator makes the MPU-6050's
 * 3.3 V), GND -> GND, SDA -> SDA (A4), SCL -> SCL (A5), AD0 open or to GND (address 0x68), INT
 * unused. The board's own pull-ups hold the bus at its 3.3 V; the sketch switches off the 5 V
 * pull-ups inside the Uno that Wire.begin() turns on.
 *
 * The chip (MPU-6000/MPU-6050 Register Map and Descriptions, RM-MPU-6000A-00 rev. 4.2, and the
 * product specification): I2C address 0x68 with AD0 low (0x69 high); a write sets the register
 * pointer, then writes consecutive registers; a read returns consecutive registers.
 * SMPLRT_DIV 0x19 (sample rate = 1 kHz / (1 + div) with the low-pass filter on); CONFIG 0x1A
 * (bits 2:0 DLPF_CFG; 5: accelerometer bandwidth 10 Hz, delay 13.8 ms); ACCEL_CONFIG 0x1C
 * (bits 4:3 AFS_SEL: +-2, 4, 8, 16 g; 16384, 8192, 4096, 2048 LSB/g; bits 7:5 self-test, off);
 * INT_ENABLE 0x38 (bit 0 DATA_RDY_EN); INT_STATUS 0x3A (bit 0 DATA_RDY_INT, cleared by reading
 * it); ACCEL_XOUT_H 0x3B .. ACCEL_ZOUT_L 0x40 (16-bit two's complement, high byte first; a burst
 * read gives the three axes of one sampling instant); PWR_MGMT_1 0x6B (bit 7 DEVICE_RESET, bit 6
 * SLEEP, set at power-on; bits 2:0 CLKSEL, 1 = the X gyroscope's PLL, which the product
 * specification recommends over the internal oscillator); WHO_AM_I 0x75 = 0x68.
 *
 * Start-up: check WHO_AM_I, reset, wake with the PLL clock, set 100 Hz sampling, the 10 Hz
 * low-pass filter (against aliasing in the 20 Hz samples, above the swing's few Hz), +-2 g and
 * the data-ready flag, and read them back. A chip that fails (no answer, or
 * another WHO_AM_I: some boards sold as GY-521 carry an MPU-6500, 0x70) sends a header with
 * sensor=MPU-6050-FAULT and no samples. Then every PERIOD_US: one burst from INT_STATUS to
 * ACCEL_ZOUT_L and one sample line; status bit 0 = the chip did not answer on the bus, bit 1 =
 * no new sample since the last one (the chip is asleep, e.g. after a brown-out of the sensor:
 * the sketch configures it again). The host drops flagged samples. The header goes out at start,
 * every HEADER_EVERY samples, and when the host sends '?'.
 */
#include <Wire.h>

#include "cadcog_protocol.h"

static const uint32_t BAUD = 115200;
static const uint32_t RATE_HZ = 20;
static const char RATE_TEXT[] = "20";
static const uint16_t HEADER_EVERY = 40; /* samples: every 2 s at 20 Hz */
static const uint32_t PERIOD_US = 1000000UL / RATE_HZ;
static const uint32_t I2C_HZ = 400000;  /* fast mode */

static const uint8_t MPU_ADDRESS = 0x68;
static const uint8_t REG_SMPLRT_DIV = 0x19;
static const uint8_t REG_CONFIG = 0x1A;
static const uint8_t REG_ACCEL_CONFIG = 0x1C;
static const uint8_t REG_INT_ENABLE = 0x38;
static const uint8_t REG_INT_STATUS = 0x3A;
static const uint8_t REG_PWR_MGMT_1 = 0x6B;
static const uint8_t REG_WHO_AM_I = 0x75;
static const uint8_t WHO_AM_I = 0x68;
static const uint8_t PWR_DEVICE_RESET = 0x80;
static const uint8_t PWR_CLOCK_PLL_X = 0x01; /* SLEEP clear: awake */
static const uint8_t DATA_RDY = 0x01;        /* INT_ENABLE and INT_STATUS bit 0 */

/* The configuration, and what the header says of it (keep them together). */
static const uint8_t SMPLRT_DIV_VALUE = 9;        /* 1 kHz / (1 + 9) = 100 Hz */
static const uint8_t CONFIG_VALUE = 5;            /* DLPF_CFG 5: 10 Hz, 13.8 ms */
static const uint8_t ACCEL_CONFIG_VALUE = 0 << 3; /* AFS_SEL 0: +-2 g, 16384 LSB/g */
static const char LSB_G_TEXT[] = "6.103515625e-05"; /* 1 / 16384 g */
static const char FULL_SCALE_G_TEXT[] = "2";

static uint32_t next_us;
static uint32_t seq;
static uint16_t since_header;
static bool sensor_ok;

static bool write_register(uint8_t address, uint8_t value) {
  Wire.beginTransmission(MPU_ADDRESS);
  Wire.write(address);
  Wire.write(value);
  return Wire.endTransmission() == 0;
}

/* n consecutive registers from `first`; false if the chip did not answer. */
static bool read_registers(uint8_t first, uint8_t *out, uint8_t n) {
  Wire.beginTransmission(MPU_ADDRESS);
  Wire.write(first);
  if (Wire.endTransmission(false) != 0) return false; /* repeated start: keep the bus */
  if (Wire.requestFrom(MPU_ADDRESS, n) != n) return false;
  for (uint8_t i = 0; i < n; i++) out[i] = (uint8_t)Wire.read();
  return true;
}

/* Wake, sample rate, filter, range, data-ready flag; true if the registers read back so. */
static bool configure() {
  if (!(write_register(REG_PWR_MGMT_1, PWR_CLOCK_PLL_X) &&
        write_register(REG_SMPLRT_DIV, SMPLRT_DIV_VALUE) &&
        write_register(REG_CONFIG, CONFIG_VALUE) &&
        write_register(REG_ACCEL_CONFIG, ACCEL_CONFIG_VALUE) &&
        write_register(REG_INT_ENABLE, DATA_RDY)))
    return false;
  uint8_t c[4], enable, power; /* SMPLRT_DIV, CONFIG, GYRO_CONFIG, ACCEL_CONFIG */
  return read_registers(REG_SMPLRT_DIV, c, sizeof c) && c[0] == SMPLRT_DIV_VALUE &&
         c[1] == CONFIG_VALUE && c[3] == ACCEL_CONFIG_VALUE &&
         read_registers(REG_INT_ENABLE, &enable, 1) && enable == DATA_RDY &&
         read_registers(REG_PWR_MGMT_1, &power, 1) && power == PWR_CLOCK_PLL_X;
}

static bool start_sensor() {
  uint8_t who;
  if (!read_registers(REG_WHO_AM_I, &who, 1) || who != WHO_AM_I) return false;
  write_register(REG_PWR_MGMT_1, PWR_DEVICE_RESET);
  delay(100); /* the reset takes up to 100 ms */
  if (!configure()) return false;
  delay(50); /* the first samples, through the low-pass filter */
  return true;
}

/* A 16-bit two's complement value, high byte first. */
static int32_t axis(const uint8_t *b) {
  return (int16_t)(uint16_t)(((uint16_t)b[0] << 8) | b[1]);
}

static void send_header() {
  char buf[CADCOG_LINE_MAX];
  if (cadcog_format_header_accel(buf, sizeof buf, "arduino",
                                 sensor_ok ? "MPU-6050" : "MPU-6050-FAULT", RATE_TEXT, LSB_G_TEXT,
                                 FULL_SCALE_G_TEXT))
    Serial.println(buf);
  since_header = 0;
}

void setup() {
  Serial.begin(BAUD);
  Wire.begin();
  digitalWrite(SDA, LOW); /* the AVR's internal pull-ups to 5 V off: the board's pull-ups stay */
  digitalWrite(SCL, LOW);
  Wire.setClock(I2C_HZ);
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
  uint8_t r[7] = {0}; /* INT_STATUS, ACCEL_XOUT_H .. ACCEL_ZOUT_L */
  uint8_t status = 0;
  if (!read_registers(REG_INT_STATUS, r, sizeof r)) status |= 1;
  else if (!(r[0] & DATA_RDY)) status |= 2;
  seq++;
  char buf[CADCOG_LINE_MAX];
  if (cadcog_format_sample3(buf, sizeof buf, seq, t_ms, axis(r + 1), axis(r + 3), axis(r + 5),
                            status))
    Serial.println(buf);
  if (status & 2) configure();
  if (++since_header >= HEADER_EVERY) send_header();
}
