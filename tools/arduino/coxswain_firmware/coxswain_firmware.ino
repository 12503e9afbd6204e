// SPDX-License-Identifier: Apache-2.0
// coxswain Arduino Mega 2560 firmware: drives the rudder servo / thruster ESCs with Timer1
// hardware PWM, reads the RC receiver, e-stop and start switch, and talks to the NUC with the
// framed protocol of tools/arduino/PROTOCOL.md. All decisions are made by FirmwareLogic
// (include/coxswain/drivers/arduino/firmware_logic.hpp, unit-tested on the host); this file
// only moves bits between pins, timers, the serial port and that core.
//
// Pins (Mega 2560):
//   11 (OC1A)  channel 0: servo (servo+thruster layout) or port ESC (twin layout)
//   12 (OC1B)  channel 1: thruster ESC or starboard ESC
//   A8/A9/A10  RC receiver steering / throttle / mode switch (pin-change interrupt PCINT2)
//   22         e-stop loop, INPUT_PULLUP, normally-closed to GND: HIGH (pressed or broken) = stop
//   23         start switch, INPUT_PULLUP, to GND when pressed
//   5/6/7      LED red / green / blue (HIGH = on)
//   A0         supply voltage through a divider (COXSWAIN_VDIV_X100, default 10k:1k = x11.00)
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/wdt.h>
#include <util/atomic.h>

#include "coxswain/drivers/arduino/firmware_logic.hpp"

#ifndef COXSWAIN_BAUD
#define COXSWAIN_BAUD 115200UL
#endif
#ifndef COXSWAIN_VREF_MV
#define COXSWAIN_VREF_MV 5000UL
#endif
#ifndef COXSWAIN_VDIV_X100
#define COXSWAIN_VDIV_X100 1100UL
#endif
#ifndef COXSWAIN_WATCHDOG
#define COXSWAIN_WATCHDOG 1
#endif

namespace cx = coxswain::drivers::arduino;

namespace {

const uint8_t kFwMajor = 1;
const uint8_t kFwMinor = 0;
const uint8_t kFwPatch = 0;
const uint16_t kTelemetryPeriodMs = 50;  // 20 Hz
const uint16_t kTimer1Top = 40000;       // 0.5 us ticks -> 20 ms frame (50 Hz)

const uint8_t kPinEstop = 22;
const uint8_t kPinStart = 23;
const uint8_t kPinLedR = 5;
const uint8_t kPinLedG = 6;
const uint8_t kPinLedB = 7;
const uint8_t kPinSupply = A0;
const uint8_t kRcMask = 0x07;  // PK0..PK2 = A8..A10

// --- RC capture (pin-change ISR) ----------------------------------------------------------
volatile uint32_t g_rc_rise_us[cx::kRcChannels];
volatile uint16_t g_rc_width_us[cx::kRcChannels];
volatile uint8_t g_rc_new = 0;  // bit per channel: a width was measured since the last loop
volatile uint8_t g_rc_last_pins = 0;

cx::LogicConfig make_config() {
  cx::LogicConfig c;  // defaults documented in firmware_logic.hpp and PROTOCOL.md
  return c;
}

cx::FirmwareLogic g_logic(make_config());
cx::FrameDecoder g_rx;
cx::LogicOutputs g_out;
uint16_t g_tx_seq = 0;
uint8_t g_reset_cause = 0;
uint32_t g_last_telemetry_ms = 0;
uint8_t g_tx_buf[cx::kMaxFrame];

}  // namespace

ISR(PCINT2_vect) {
  const uint32_t now_us = micros();
  const uint8_t pins = PINK & kRcMask;
  const uint8_t changed = pins ^ g_rc_last_pins;
  g_rc_last_pins = pins;
  for (uint8_t c = 0; c < cx::kRcChannels; ++c) {
    const uint8_t bit = static_cast<uint8_t>(1U << c);
    if ((changed & bit) == 0) {
      continue;
    }
    if ((pins & bit) != 0) {
      g_rc_rise_us[c] = now_us;
    } else {
      const uint32_t width = now_us - g_rc_rise_us[c];
      // Longer than any RC pulse: a missed edge; let the logic's range check reject it.
      g_rc_width_us[c] = width > 0xFFFFUL ? 0xFFFFU : static_cast<uint16_t>(width);
      g_rc_new = static_cast<uint8_t>(g_rc_new | bit);
    }
  }
}

namespace {

void setup_pwm() {
  pinMode(11, OUTPUT);
  pinMode(12, OUTPUT);
  const cx::LogicConfig& c = g_logic.config();
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    TCCR1A = 0;
    TCCR1B = 0;
    ICR1 = kTimer1Top;
    OCR1A = static_cast<uint16_t>(2U * c.neutral_us[0]);
    OCR1B = static_cast<uint16_t>(2U * c.neutral_us[1]);
    TCNT1 = 0;
    // Fast PWM, TOP = ICR1 (WGM13:12:11), non-inverting OC1A/OC1B, prescaler 8 (0.5 us).
    TCCR1A = _BV(COM1A1) | _BV(COM1B1) | _BV(WGM11);
    TCCR1B = _BV(WGM13) | _BV(WGM12) | _BV(CS11);
  }
}

void apply_pwm(const cx::LogicOutputs& out) {
  // OCR1x are double-buffered in fast PWM (updated at BOTTOM), so a pulse is never cut short.
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    OCR1A = static_cast<uint16_t>(2U * out.pulse_us[0]);
    OCR1B = static_cast<uint16_t>(2U * out.pulse_us[1]);
  }
}

void setup_rc() {
  DDRK &= static_cast<uint8_t>(~kRcMask);
  PORTK &= static_cast<uint8_t>(~kRcMask);  // receivers drive the lines; no pull-ups
  g_rc_last_pins = PINK & kRcMask;
  PCMSK2 |= kRcMask;
  PCICR |= _BV(PCIE2);
}

void poll_rc(uint32_t now_ms) {
  uint8_t fresh;
  uint16_t width[cx::kRcChannels];
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    fresh = g_rc_new;
    g_rc_new = 0;
    for (uint8_t c = 0; c < cx::kRcChannels; ++c) {
      width[c] = g_rc_width_us[c];
    }
  }
  for (uint8_t c = 0; c < cx::kRcChannels; ++c) {
    if ((fresh & (1U << c)) != 0) {
      g_logic.on_rc_pulse(now_ms, c, width[c]);
    }
  }
}

void apply_led(uint8_t colour) {
  // msg::LedColour: 0 off, 1 red, 2 green, 3 blue, 4 yellow, 5 purple, 6 white.
  static const uint8_t kRgb[7] = {0, 1, 2, 4, 3, 5, 7};
  const uint8_t rgb = colour < 7 ? kRgb[colour] : 0;
  digitalWrite(kPinLedR, (rgb & 1) ? HIGH : LOW);
  digitalWrite(kPinLedG, (rgb & 2) ? HIGH : LOW);
  digitalWrite(kPinLedB, (rgb & 4) ? HIGH : LOW);
}

uint16_t read_supply_mv() {
  const uint32_t adc = static_cast<uint32_t>(analogRead(kPinSupply));
  const uint32_t mv = adc * COXSWAIN_VREF_MV * COXSWAIN_VDIV_X100 / (1023UL * 100UL);
  return mv > 0xFFFFUL ? 0xFFFFU : static_cast<uint16_t>(mv);
}

void send_frame(size_t n) {
  if (n > 0) {
    Serial.write(g_tx_buf, n);
  }
  ++g_tx_seq;
}

void send_ready() {
  cx::Ready r;
  const cx::LogicConfig& c = g_logic.config();
  r.protocol_version = cx::kProtocolVersion;
  r.fw_major = kFwMajor;
  r.fw_minor = kFwMinor;
  r.fw_patch = kFwPatch;
  r.failsafe_ms = c.failsafe_ms;
  r.neutral_us[0] = c.neutral_us[0];
  r.neutral_us[1] = c.neutral_us[1];
  r.reset_cause = g_reset_cause;
  r.rc_channels = cx::kRcChannels;
  send_frame(cx::encode(r, g_tx_seq, g_tx_buf, sizeof(g_tx_buf)));
}

void send_pong(uint32_t token, uint32_t now_ms) {
  cx::Pong p;
  p.token = token;
  p.uptime_ms = now_ms;
  send_frame(cx::encode(p, g_tx_seq, g_tx_buf, sizeof(g_tx_buf)));
}

void send_telemetry(uint32_t now_ms) {
  cx::Telemetry t;
  g_logic.fill_telemetry(now_ms, g_out, g_rx.stats(), read_supply_mv(), &t);
  send_frame(cx::encode(t, g_tx_seq, g_tx_buf, sizeof(g_tx_buf)));
}

void handle_frame(const cx::Frame& f, uint32_t now_ms) {
  cx::SetOutputs cmd;
  cx::Ping ping;
  cx::Hello hello;
  if (cx::parse(f, &cmd)) {
    (void)g_logic.on_set_outputs(now_ms, f.seq, cmd);
  } else if (cx::parse(f, &ping)) {
    send_pong(ping.token, now_ms);
  } else if (cx::parse(f, &hello)) {
    g_logic.on_hello();
    send_ready();
  }
  // Anything else (board->host types, malformed payloads) is ignored.
}

void poll_serial() {
  // Bounded so a byte flood cannot starve the outputs.
  for (uint8_t i = 0; i < 64 && Serial.available() > 0; ++i) {
    const int b = Serial.read();
    if (b < 0) {
      break;
    }
    if (g_rx.push(static_cast<uint8_t>(b))) {
      handle_frame(g_rx.frame(), millis());
    }
  }
}

}  // namespace

void setup() {
  g_reset_cause = MCUSR;
  MCUSR = 0;
  wdt_disable();
  setup_pwm();  // neutral pulses start immediately: the ESC arming hold begins now
  pinMode(kPinEstop, INPUT_PULLUP);
  pinMode(kPinStart, INPUT_PULLUP);
  pinMode(kPinLedR, OUTPUT);
  pinMode(kPinLedG, OUTPUT);
  pinMode(kPinLedB, OUTPUT);
  apply_led(0);
  setup_rc();
  Serial.begin(COXSWAIN_BAUD);
  const uint32_t now_ms = millis();
  g_logic.reset(now_ms);
  g_last_telemetry_ms = now_ms;
  send_ready();
#if COXSWAIN_WATCHDOG
  // A hung CPU would keep the hardware PWM running with the last pulses: reset instead.
  wdt_enable(WDTO_250MS);
#endif
}

void loop() {
#if COXSWAIN_WATCHDOG
  wdt_reset();
#endif
  const uint32_t now_ms = millis();
  poll_serial();
  poll_rc(now_ms);
  cx::SwitchInputs in;
  in.estop = digitalRead(kPinEstop) == HIGH;
  in.start_switch = digitalRead(kPinStart) == LOW;
  g_out = g_logic.step(now_ms, in);
  apply_pwm(g_out);
  apply_led(g_out.led);
  if (static_cast<uint32_t>(now_ms - g_last_telemetry_ms) >= kTelemetryPeriodMs) {
    g_last_telemetry_ms = now_ms;
    send_telemetry(now_ms);
  }
}
