/* Murata SCL3300 SPI frames (datasheet SCL3300-D01): 32-bit frames, MSB first, SPI mode 0.
 *
 * Frame: [31] R/W, [30:26] address, [25:24] return status (RS, responses only), [23:8] data,
 * [7:0] CRC-8 over bits [31:8] (polynomial 0x1D, initial value 0xFF, result inverted).
 * Off-frame protocol: the response to a request arrives during the NEXT frame.
 * RS: 00 start-up in progress, 01 normal, 10 self-test running, 11 error.
 * Angles: ANG_X/Y/Z are int16, angle = raw / 2^14 * 90 degrees.
 *
 * Plain C, no Arduino dependency: tests/bench/test_firmware.py checks every command's CRC.
 */
#ifndef SCL3300_FRAMES_H
#define SCL3300_FRAMES_H

#include <stdint.h>

#define SCL3300_READ_ACC_X 0x040000F7UL
#define SCL3300_READ_ACC_Y 0x080000FDUL
#define SCL3300_READ_ACC_Z 0x0C0000FBUL
#define SCL3300_READ_STO 0x100000E9UL
#define SCL3300_READ_TEMPERATURE 0x140000EFUL
#define SCL3300_READ_STATUS 0x180000E5UL
#define SCL3300_READ_ERR_FLAG1 0x1C0000E3UL
#define SCL3300_READ_ERR_FLAG2 0x200000C1UL
#define SCL3300_READ_ANG_X 0x240000C7UL
#define SCL3300_READ_ANG_Y 0x280000CDUL
#define SCL3300_READ_ANG_Z 0x2C0000CBUL
#define SCL3300_READ_CMD 0x340000DFUL
#define SCL3300_READ_WHOAMI 0x40000091UL
#define SCL3300_ENABLE_ANGLES 0xB0001F6FUL
#define SCL3300_MODE_1 0xB400001FUL
#define SCL3300_MODE_2 0xB4000102UL
#define SCL3300_MODE_3 0xB4000225UL
#define SCL3300_MODE_4 0xB4000338UL /* inclination mode, low noise */
#define SCL3300_POWER_DOWN 0xB400046BUL
#define SCL3300_SW_RESET 0xB4002098UL
#define SCL3300_BANK_0 0xFC000073UL

#define SCL3300_WHOAMI 0xC1
#define SCL3300_RS_NORMAL 1

/* CRC-8 of the upper 24 bits of a frame. */
static inline uint8_t scl3300_crc8(uint32_t frame) {
  uint8_t crc = 0xFF;
  for (int8_t bit = 31; bit >= 8; bit--) {
    uint8_t in = (uint8_t)((frame >> bit) & 1u);
    uint8_t top = (uint8_t)((crc >> 7) & 1u);
    crc = (uint8_t)(crc << 1);
    if (in ^ top) crc ^= 0x1D;
  }
  return (uint8_t)~crc;
}

static inline uint8_t scl3300_crc_ok(uint32_t frame) {
  return scl3300_crc8(frame) == (uint8_t)(frame & 0xFF);
}
static inline uint8_t scl3300_rs(uint32_t frame) { return (uint8_t)((frame >> 24) & 3u); }
static inline uint16_t scl3300_data(uint32_t frame) { return (uint16_t)((frame >> 8) & 0xFFFFu); }

#endif /* SCL3300_FRAMES_H */
