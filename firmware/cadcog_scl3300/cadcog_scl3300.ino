/* cadcog: a Murata SCL3300 dual-axis MEMS inclinometer on SPI, streamed in the cadcog line
 * protocol (docs/bench.md) as raw ANG_X / ANG_Y (angle = raw / 2^14 * 90 degrees).
 *
 * Wiring (docs/bench.md has the table; the SCL3300 is a 3.3 V part: use a 3.3 V board or
 * level shifters): SCK -> SCK, MOSI -> MOSI, MISO -> MISO, CSB -> PIN_CS, VDD/GND.
 *
 * Start-up (datasheet): software reset, mode 4 (inclination, low noise), enable the angle
 * outputs, wait for the filters to settle, read STATUS three times and require RS = 01, check
 * WHOAMI = 0xC1. Then every PERIOD_US: read ANG_X and ANG_Y (off-frame: each response arrives
 * with the next request), check each response's CRC and return status, and send one sample
 * line; status bit 0 = a CRC error, bit 1 = RS not normal (the host drops such samples). A
 * sensor that fails its start-up sends a header with sensor=SCL3300-FAULT and no samples.
 */
#include <SPI.h>

#include "cadcog_protocol.h"
#include "scl3300_frames.h"

static const uint8_t PIN_CS = 10;
static const uint32_t BAUD = 115200;
static const uint32_t RATE_HZ = 20;
static const char RATE_TEXT[] = "20";
static const char DEG_PER_LSB_TEXT[] = "0.0054931640625"; /* 90 / 2^14 */
static const uint16_t HEADER_EVERY = 40;
static const uint32_t PERIOD_US = 1000000UL / RATE_HZ;
static const SPISettings SCL_SPI(2000000, MSBFIRST, SPI_MODE0);

static uint32_t next_us;
static uint32_t seq;
static uint16_t since_header;
static bool sensor_ok;

static uint32_t transfer(uint32_t request) {
  uint32_t response = 0;
  SPI.beginTransaction(SCL_SPI);
  digitalWrite(PIN_CS, LOW);
  for (int8_t shift = 24; shift >= 0; shift -= 8)
    response = (response << 8) | SPI.transfer((uint8_t)(request >> shift));
  digitalWrite(PIN_CS, HIGH);
  SPI.endTransaction();
  delayMicroseconds(10); /* minimum time between frames */
  return response;
}

static void send_header() {
  char buf[CADCOG_LINE_MAX];
  if (cadcog_format_header_angle(buf, sizeof buf, "arduino",
                                 sensor_ok ? "SCL3300" : "SCL3300-FAULT", RATE_TEXT,
                                 DEG_PER_LSB_TEXT))
    Serial.println(buf);
  since_header = 0;
}

static bool start_sensor() {
  transfer(SCL3300_SW_RESET);
  delay(1);
  transfer(SCL3300_MODE_4);
  transfer(SCL3300_ENABLE_ANGLES);
  delay(100); /* output filter settling in modes 3 and 4 */
  transfer(SCL3300_READ_STATUS);
  transfer(SCL3300_READ_STATUS);
  uint32_t status = transfer(SCL3300_READ_WHOAMI); /* response to the last STATUS read */
  uint32_t who = transfer(SCL3300_READ_STATUS);   /* response to WHOAMI */
  return scl3300_crc_ok(status) && scl3300_rs(status) == SCL3300_RS_NORMAL &&
         scl3300_crc_ok(who) && (scl3300_data(who) & 0xFF) == SCL3300_WHOAMI;
}

static uint8_t check(uint32_t response) {
  uint8_t flags = 0;
  if (!scl3300_crc_ok(response)) flags |= 1;
  if (scl3300_rs(response) != SCL3300_RS_NORMAL) flags |= 2;
  return flags;
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
  transfer(SCL3300_READ_ANG_X);
  uint32_t rx = transfer(SCL3300_READ_ANG_Y);
  uint32_t ry = transfer(SCL3300_READ_STATUS);
  uint8_t status = (uint8_t)(check(rx) | check(ry));
  seq++;
  char buf[CADCOG_LINE_MAX];
  if (cadcog_format_sample(buf, sizeof buf, seq, t_ms, (int16_t)scl3300_data(rx),
                           (int16_t)scl3300_data(ry), status))
    Serial.println(buf);
  if (++since_header >= HEADER_EVERY) send_header();
}
