/* cadcog: the paper's analog dual-axis inclinometer (e.g. Posital Fraba ACS-060) read by an
 * Arduino Uno's 10-bit ADC, streamed in the cadcog line protocol (docs/bench.md).
 *
 * Wiring (docs/bench.md has the table): sensor X output -> A0, Y output -> A1, sensor ground
 * -> GND, sensor supply as its datasheet says (never above 5 V on A0/A1). USB serial, or a
 * wireless serial bridge on pins 0/1 at the same baud rate.
 *
 * Every PERIOD_US (fixed rate, scheduled on micros() without drift) the sketch sums
 * OVERSAMPLE conversions of each channel, interleaved, and sends one sample line with the sums;
 * the host divides by OVERSAMPLE (the header says it) and converts counts to degrees with the
 * rig file's sensor model. The header goes out at start, every HEADER_EVERY samples, and when
 * the host sends '?'.
 */
#include "cadcog_protocol.h"

static const uint8_t PIN_X = A0;
static const uint8_t PIN_Y = A1;
static const uint32_t BAUD = 115200;
static const uint32_t RATE_HZ = 20;
static const char RATE_TEXT[] = "20";         /* RATE_HZ as text, for the header */
static const uint8_t OVERSAMPLE = 16;         /* 16 x 2 conversions: ~3.6 ms per sample */
static const int ADC_BITS = 10;
static const char VREF_TEXT[] = "5";          /* AREF: the 5 V supply (analogReference DEFAULT) */
static const uint16_t HEADER_EVERY = 40;      /* samples: every 2 s at 20 Hz */
static const uint32_t PERIOD_US = 1000000UL / RATE_HZ;

static uint32_t next_us;
static uint32_t seq;
static uint16_t since_header;

static void send_header() {
  char buf[CADCOG_LINE_MAX];
  if (cadcog_format_header_adc(buf, sizeof buf, "arduino-uno", "ACS-060", RATE_TEXT, ADC_BITS,
                               VREF_TEXT, OVERSAMPLE))
    Serial.println(buf);
  since_header = 0;
}

void setup() {
  Serial.begin(BAUD);
  analogReference(DEFAULT);
  analogRead(PIN_X); /* the first conversion after a reference change is unreliable */
  analogRead(PIN_Y);
  send_header();
  next_us = micros();
}

void loop() {
  while (Serial.available() > 0) {
    if (Serial.read() == '?') send_header();
  }
  uint32_t now = micros();
  if ((int32_t)(now - next_us) < 0) return; /* not yet: wrap-safe comparison */
  if (now - next_us > 4 * PERIOD_US) next_us = now; /* fell far behind: resynchronise */
  next_us += PERIOD_US;
  uint32_t t_ms = millis();
  int32_t sum_x = 0, sum_y = 0;
  for (uint8_t i = 0; i < OVERSAMPLE; i++) {
    sum_x += analogRead(PIN_X);
    sum_y += analogRead(PIN_Y);
  }
  seq++;
  char buf[CADCOG_LINE_MAX];
  if (cadcog_format_sample(buf, sizeof buf, seq, t_ms, sum_x, sum_y, 0)) Serial.println(buf);
  if (++since_header >= HEADER_EVERY) send_header();
}
