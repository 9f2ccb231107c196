// The harness's side of the emulated sensor chips: the virtual clock, the harness's options, the
// test's x, y, z counts, and the bus calls each emulated chip answers (chip_*.cpp: the test
// links the one its sketch talks to).
#pragma once
#include <stddef.h>
#include <stdint.h>

// Virtual clock (microseconds since the start of the run).
uint64_t host_now_us();
void host_advance_us(uint32_t us);

// The value of the option --NAME=VALUE given to the harness, or nullptr.
const char *host_option(const char *name);

// The next x, y, z counts the emulated chip converts: the lines "x y z" of --vectors=FILE in
// order (cycled when the run outlasts them), or a ramp without it.
void host_next_xyz(int32_t xyz[3]);

// Implemented by the emulated chip.
void chip_start();                         // before setup(): power-on state, options
void chip_pin(uint8_t pin, uint8_t value);  // digitalWrite (chip selects)
uint8_t chip_spi_transfer(uint8_t mosi);   // one SPI byte, full duplex: returns MISO
bool chip_i2c_write(uint8_t address, const uint8_t *data, size_t n);  // false: no ACK
bool chip_i2c_read(uint8_t address, uint8_t *data, size_t n);         // false: no ACK
void chip_finish();                        // after the run: report to stderr
