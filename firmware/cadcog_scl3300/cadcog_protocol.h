/* cadcog line protocol, version 1: formatting on the device side.
 *
 * Every line is "$BODY*CC" + "\r\n", CC the CRC-8/SMBUS (poly 0x07, init 0) of BODY in two
 * upper-case hex digits. Header: "$CCH,proto=1,device=...,sensor=...,value=...,..."; sample:
 * "$CCS,seq,t_ms,x,y,status", or "$CCS,seq,t_ms,x,y,z,status" from a three-axis accelerometer
 * (value=accel). Specification: docs/bench.md; reader: cadcog/bench/protocol.py.
 *
 * Plain C, no Arduino dependency (tests/bench/test_firmware.py compiles it on the host).
 * The same file sits in every sketch folder (the Arduino IDE compiles a sketch's own folder
 * only); the test checks the copies are identical.
 */
#ifndef CADCOG_PROTOCOL_H
#define CADCOG_PROTOCOL_H

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define CADCOG_PROTOCOL_VERSION 1
#define CADCOG_LINE_MAX 160

static inline uint8_t cadcog_crc8(const char *s, size_t n) {
  uint8_t c = 0;
  for (size_t i = 0; i < n; i++) {
    c ^= (uint8_t)s[i];
    for (uint8_t b = 0; b < 8; b++) c = (c & 0x80) ? (uint8_t)((c << 1) ^ 0x07) : (uint8_t)(c << 1);
  }
  return c;
}

/* buf holds "$BODY" of length len: append "*CC". Returns the new length, 0 if it does not fit. */
static inline size_t cadcog_finish(char *buf, size_t cap, size_t len) {
  static const char hex[] = "0123456789ABCDEF";
  if (len < 2 || len + 4 > cap) return 0;
  uint8_t c = cadcog_crc8(buf + 1, len - 1);
  buf[len++] = '*';
  buf[len++] = hex[c >> 4];
  buf[len++] = hex[c & 15];
  buf[len] = '\0';
  return len;
}

static inline size_t cadcog_checked(char *buf, size_t cap, int n) {
  if (n < 0 || (size_t)n >= cap) return 0;
  return cadcog_finish(buf, cap, (size_t)n);
}

/* One sample: seq and t_ms wrap at 2^32 (the host unwraps them). */
static inline size_t cadcog_format_sample(char *buf, size_t cap, uint32_t seq, uint32_t t_ms,
                                          int32_t x, int32_t y, uint8_t status) {
  return cadcog_checked(buf, cap, snprintf(buf, cap, "$CCS,%lu,%lu,%ld,%ld,%u",
                                           (unsigned long)seq, (unsigned long)t_ms, (long)x,
                                           (long)y, (unsigned)status));
}

/* One sample of a three-axis device (value=accel): x, y and z. */
static inline size_t cadcog_format_sample3(char *buf, size_t cap, uint32_t seq, uint32_t t_ms,
                                           int32_t x, int32_t y, int32_t z, uint8_t status) {
  return cadcog_checked(buf, cap, snprintf(buf, cap, "$CCS,%lu,%lu,%ld,%ld,%ld,%u",
                                           (unsigned long)seq, (unsigned long)t_ms, (long)x,
                                           (long)y, (long)z, (unsigned)status));
}

/* Header of an ADC device: x and y are sums of `oversample` conversions. Numbers that may not
 * be integers are passed as text (avr-libc's printf has no %f). */
static inline size_t cadcog_format_header_adc(char *buf, size_t cap, const char *device,
                                              const char *sensor, const char *rate_hz,
                                              int adc_bits, const char *vref_v, int oversample) {
  return cadcog_checked(
      buf, cap,
      snprintf(buf, cap,
               "$CCH,proto=%d,device=%s,sensor=%s,value=adc_sum,rate_hz=%s,adc_bits=%d,"
               "vref_v=%s,oversample=%d",
               CADCOG_PROTOCOL_VERSION, device, sensor, rate_hz, adc_bits, vref_v, oversample));
}

/* Header of a digital sensor sending angles of `deg_per_lsb` degrees per unit. */
static inline size_t cadcog_format_header_angle(char *buf, size_t cap, const char *device,
                                                const char *sensor, const char *rate_hz,
                                                const char *deg_per_lsb) {
  return cadcog_checked(buf, cap,
                        snprintf(buf, cap,
                                 "$CCH,proto=%d,device=%s,sensor=%s,value=angle,rate_hz=%s,"
                                 "deg_per_lsb=%s",
                                 CADCOG_PROTOCOL_VERSION, device, sensor, rate_hz, deg_per_lsb));
}

/* Header of a three-axis accelerometer sending raw counts of `lsb_g` g (standard gravity) each,
 * set to a range of +-`full_scale_g` g. The host's reader writes lsb_g as Python's repr() of the
 * float and full_scale_g in its shortest %g form: pass them so for byte-identical lines. */
static inline size_t cadcog_format_header_accel(char *buf, size_t cap, const char *device,
                                                const char *sensor, const char *rate_hz,
                                                const char *lsb_g, const char *full_scale_g) {
  return cadcog_checked(buf, cap,
                        snprintf(buf, cap,
                                 "$CCH,proto=%d,device=%s,sensor=%s,value=accel,rate_hz=%s,"
                                 "lsb_g=%s,full_scale_g=%s",
                                 CADCOG_PROTOCOL_VERSION, device, sensor, rate_hz, lsb_g,
                                 full_scale_g));
}

#endif /* CADCOG_PROTOCOL_H */
