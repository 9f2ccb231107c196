// Runs a sketch's setup() and loop() for RUN_S virtual seconds, printing its serial output.
// Analog: conversion k of channel X reads 300 + k % 7, of channel Y 700 + (3 k) % 11.
// The host asks for a header ('?') once, at 1.5 s. The SPI and I2C buses go to the emulated chip
// linked in with the harness (chip_*.cpp, see host_chip.h); options --NAME=VALUE are the chip's.
#include <stdlib.h>

#include "Arduino.h"
#include "SPI.h"
#include "Wire.h"
#include "host_chip.h"

#ifndef RUN_S
#define RUN_S 5
#endif

HostSerial Serial;
HostSPI SPI;
TwoWire Wire;
static uint64_t now_us = 1000;
static uint32_t conv_x, conv_y;

uint64_t host_now_us() { return now_us; }
void host_advance_us(uint32_t us) { now_us += us; }

uint32_t micros() { return (uint32_t)now_us; }
uint32_t millis() { return (uint32_t)(now_us / 1000); }
void delay(uint32_t ms) { now_us += 1000ull * ms; }
void delayMicroseconds(uint32_t us) { now_us += us; }
void analogReference(uint8_t) {}
void pinMode(uint8_t, uint8_t) {}
int analogRead(uint8_t pin) {
  now_us += 112;  // one conversion at the default prescaler
  if (pin == A0) return 300 + (conv_x++ % 7);
  return 700 + ((3 * conv_y++) % 11);
}
static bool asked = false;  // the host asks for a header once, at 1.5 s
int HostSerial::available() { return !asked && now_us > 1500000 ? 1 : 0; }
int HostSerial::read() {
  asked = true;
  return '?';
}

void digitalWrite(uint8_t pin, uint8_t value) { chip_pin(pin, value); }
uint8_t HostSPI::transfer(uint8_t b) { return chip_spi_transfer(b); }

// I2C at 400 kHz: about 25 us a byte with its acknowledge bit, start and stop included.
void TwoWire::beginTransmission(uint8_t address) {
  tx_address_ = address;
  tx_len_ = 0;
}
size_t TwoWire::write(uint8_t b) {
  if (tx_len_ >= sizeof tx_) return 0;
  tx_[tx_len_++] = b;
  return 1;
}
uint8_t TwoWire::endTransmission(bool) {
  now_us += 25 * (tx_len_ + 1);
  return chip_i2c_write(tx_address_, tx_, tx_len_) ? 0 : 2;
}
uint8_t TwoWire::requestFrom(uint8_t address, uint8_t quantity, bool) {
  rx_len_ = rx_pos_ = 0;
  if (quantity > sizeof rx_) quantity = sizeof rx_;
  now_us += 25 * (quantity + 1);
  if (!chip_i2c_read(address, rx_, quantity)) return 0;
  rx_len_ = quantity;
  return quantity;
}
int TwoWire::available() { return (int)(rx_len_ - rx_pos_); }
int TwoWire::read() { return rx_pos_ < rx_len_ ? rx_[rx_pos_++] : -1; }

static int host_argc;
static char **host_argv;
const char *host_option(const char *name) {
  size_t n = strlen(name);
  for (int i = 1; i < host_argc; i++) {
    const char *a = host_argv[i];
    if (a[0] == '-' && a[1] == '-' && strncmp(a + 2, name, n) == 0 && a[2 + n] == '=')
      return a + 3 + n;
  }
  return nullptr;
}

static int32_t (*vectors)[3];
static size_t n_vectors, next_vector;
static void load_vectors() {
  const char *path = host_option("vectors");
  if (!path) return;
  FILE *f = fopen(path, "r");
  if (!f) {
    fprintf(stderr, "cannot open %s\n", path);
    exit(2);
  }
  long x, y, z;
  size_t cap = 0;
  while (fscanf(f, "%ld %ld %ld", &x, &y, &z) == 3) {
    if (n_vectors == cap) {
      cap = cap ? 2 * cap : 256;
      vectors = (int32_t(*)[3])realloc(vectors, cap * sizeof *vectors);
    }
    vectors[n_vectors][0] = (int32_t)x;
    vectors[n_vectors][1] = (int32_t)y;
    vectors[n_vectors][2] = (int32_t)z;
    n_vectors++;
  }
  fclose(f);
}
void host_next_xyz(int32_t xyz[3]) {
  size_t k = next_vector++;
  for (int i = 0; i < 3; i++)
    xyz[i] = n_vectors ? vectors[k % n_vectors][i] : (int32_t)(1000 * (i + 1) + 7 * (int32_t)k);
}

void setup();
void loop();

int main(int argc, char **argv) {
  host_argc = argc;
  host_argv = argv;
  load_vectors();
  chip_start();
  setup();
  while (now_us < (uint64_t)RUN_S * 1000000ull) {
    loop();
    now_us += 50;
  }
  chip_finish();
  return 0;
}
