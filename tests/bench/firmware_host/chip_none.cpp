// No chip on either bus (the analog sketch): SPI reads 0xFF, no I2C address answers.
#include "host_chip.h"

void chip_start() {}
void chip_pin(uint8_t, uint8_t) {}
uint8_t chip_spi_transfer(uint8_t) { return 0xFF; }
bool chip_i2c_write(uint8_t, const uint8_t *, size_t) { return false; }
bool chip_i2c_read(uint8_t, uint8_t *, size_t) { return false; }
void chip_finish() {}
