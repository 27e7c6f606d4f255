// SPDX-License-Identifier: Apache-2.0
// The Console-style transcript, shared by the session runner (sim/session.cpp) and the
// virtual module (sim/virtual.cpp):
//   [    1.234567 ms] > 02:1A,01,00                 host -> core (address: data)
//   [    2.000000 ms] < 02:04,0E,01,F4              pin 4 timer: 500 ticks = 800.0 us
//   [    2.100000 ms] < 2:cmd index error           (02:80,0A)
//   [    3.000000 ms] * raw input 17                pin 2 transition latch fired
// The protocol's numbers and names come from bsd_protocol.h (generated from
// tools/protocol.toml). The core's parameters come from the build: the Makefile passes the
// same values to Verilator (-G) and here (-DBSD_*), from one set of make variables.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "bsd_protocol.h"

#if !defined(BSD_CLK_HZ) || !defined(BSD_MODULE_ADDR) || !defined(BSD_NUM_PINS) || \
    !defined(BSD_PIN_ID_BASE) || !defined(BSD_TIMER_ID_BASE) || !defined(BSD_TRANS_ID_BASE)
#error "build with make (sim-build, virtual-build): BSD_CLK_HZ, BSD_MODULE_ADDR, BSD_NUM_PINS, BSD_*_ID_BASE = the model's -G values"
#endif

namespace bsdsim {

// The core's parameters this program was built for (the same as the model's).
constexpr uint64_t kClkHz = BSD_CLK_HZ;
constexpr int kModuleAddr = BSD_MODULE_ADDR;
constexpr int kNumPins = BSD_NUM_PINS;
constexpr int kPinIdBase = BSD_PIN_ID_BASE;
constexpr int kTimerIdBase = BSD_TIMER_ID_BASE;
constexpr int kTransIdBase = BSD_TRANS_ID_BASE;
static_assert(kNumPins >= 1 && kNumPins <= 64, "NUM_PINS is 1..64");
constexpr double kTickUs = 1e6 / bsd::TICK_HZ;

// One transcript line: the simulated time, what happened, what it means.
inline void print_line(double seconds, const std::string& what, const std::string& meaning) {
    std::printf("[%12.6f ms] %-28s %s\n", seconds * 1e3, what.c_str(), meaning.c_str());
}

inline const char* message_name(uint8_t code) {
    const char* text = bsd::message_text(code);
    return text ? text : "message";
}

// Console style: address, then the data bytes (with_len adds N). A packet is address, N, data.
inline std::string hex_packet(const std::vector<uint8_t>& p, bool with_len) {
    char b[8];
    std::string s;
    std::snprintf(b, sizeof b, "%02X:", p[0]);
    s += b;
    for (size_t i = with_len ? 1 : 2; i < p.size(); ++i) {
        std::snprintf(b, sizeof b, i + 1 < p.size() ? "%02X," : "%02X", p[i]);
        s += b;
    }
    return s;
}

// Bytes without packet structure: 03,02.
inline std::string hex_bytes(const std::vector<uint8_t>& bytes) {
    char b[8];
    std::string s;
    for (size_t i = 0; i < bytes.size(); ++i) {
        std::snprintf(b, sizeof b, i + 1 < bytes.size() ? "%02X," : "%02X", bytes[i]);
        s += b;
    }
    return s;
}

inline std::string decode_cfg(uint8_t c) {
    std::string s = (c & bsd::DIGCFG_IODIR) ? "input" : "output";
    if (c & bsd::DIGCFG_ENA) s += std::string(", latch on ") + ((c & bsd::DIGCFG_TRG) ? "0->1" : "1->0");
    if (c & bsd::DIGCFG_TMODE) s += std::string(", width timer of ") + ((c & bsd::DIGCFG_TSTATE) ? "high" : "low");
    else if (c & bsd::DIGCFG_TSTATE) s += ", edge timer to high";
    if (c & bsd::DIGCFG_FIXED) s += ", fixed";
    return s;
}

// The meaning of a packet from the core ("" when there is nothing to add).
inline std::string decode_core(const std::vector<uint8_t>& p) {
    char b[96];
    const size_t n = p[1];
    if (n == 0) return "resync reply";
    const uint8_t cmd = p[2];
    if (cmd == bsd::CMD_MSG && n == bsd::MSG_N) return "";
    if (cmd == bsd::CMD_HB && n == 2) return p[3] == bsd::HB_UP ? "heartbeat UP" : "heartbeat DOWN";
    if (cmd == bsd::CMD_DIG_CFG && n == 3) {
        std::snprintf(b, sizeof b, "pin %d config 0x%02X: %s", p[3], p[4], decode_cfg(p[4]).c_str());
        return b;
    }
    if (cmd == bsd::CMD_DEV_VAL && n == 3) {
        std::snprintf(b, sizeof b, "pin %d level %d", p[3] - kPinIdBase, p[4]);
        return b;
    }
    if (cmd == bsd::CMD_DEV_VAL && n == 4) {
        const unsigned ticks = (p[4] << 8) | p[5];
        if (ticks == 0)
            std::snprintf(b, sizeof b, "pin %d timer: timeout", p[3] - kTimerIdBase);
        else
            std::snprintf(b, sizeof b, "pin %d timer: %u ticks = %.1f us", p[3] - kTimerIdBase, ticks,
                          ticks * kTickUs);
        return b;
    }
    if (cmd == bsd::CMD_DEBUG) return "debug echo";
    return "";
}

struct Line {
    std::string what, meaning;
};

// A whole packet from the core as a transcript line: messages by name, the rest in hex.
inline Line core_packet(const std::vector<uint8_t>& p) {
    if (p.size() >= 4 && p[1] == bsd::MSG_N && p[2] == bsd::CMD_MSG) {
        char b[48];
        std::snprintf(b, sizeof b, "< %d:%s", p[0], message_name(p[3]));
        return {b, "(" + hex_packet(p, false) + ")"};
    }
    return {"< " + hex_packet(p, false), decode_core(p)};
}

inline std::string devcode_text(uint8_t dev) {
    const bool host = dev & bsd::DEVCODE_HOST, rflx = dev & bsd::DEVCODE_RFLX;
    return host && rflx ? "HOST, RFLX" : host ? "HOST" : rflx ? "RFLX" : "value discarded";
}

// The meaning of a whole packet from the host, read as the core reads it (§2, §3).
inline std::string decode_host(const std::vector<uint8_t>& p) {
    char b[96];
    const size_t n = p[1];
    if (p[0] == bsd::ADDR_RESYNC && n == 0) return "resync probe";
    if (p[0] != kModuleAddr) {
        std::snprintf(b, sizeof b, "not for module %d: ignored", kModuleAddr);
        return b;
    }
    if (n == 0) return "empty: ignored";
    const uint8_t cmd = p[2];
    const size_t args = n - 1;
    const char* extra = args > 2 ? " (too long)" : "";
    switch (cmd) {
        case bsd::CMD_DIG_CFG:
            if (args == 1) std::snprintf(b, sizeof b, "query pin %d config", p[3]);
            else if (args >= 2)
                std::snprintf(b, sizeof b, "set pin %d config 0x%02X: %s%s", p[3], p[4],
                              decode_cfg(p[4] & bsd::DIGCFG_STORED).c_str(), extra);
            else return "";
            return b;
        case bsd::CMD_DIG_IO:
            if (args == 1)
                std::snprintf(b, sizeof b, "read pin %d (%s)", p[3] & bsd::DEVCODE_PIN, devcode_text(p[3]).c_str());
            else if (args >= 2) std::snprintf(b, sizeof b, "drive pin %d %s%s", p[3], p[4] ? "high" : "low", extra);
            else return "";
            return b;
        case bsd::CMD_DIG_RST:
            if (args < 1) return "";
            std::snprintf(b, sizeof b, "re-arm pin %d latch%s", p[3], args > 1 ? " (too long)" : "");
            return b;
        case bsd::CMD_PTIME_RD:
            if (args < 1) return "";
            std::snprintf(b, sizeof b, "time pin %d (%s)%s", p[3] & bsd::DEVCODE_PIN, devcode_text(p[3]).c_str(),
                          args > 1 ? " (too long)" : "");
            return b;
        case bsd::CMD_HB:
            if (args >= 1 && p[3] == bsd::HB_UP + bsd::HB_ANSWER_OFFSET) return "heartbeat UP answered";
            if (args >= 1 && p[3] == bsd::HB_DOWN + bsd::HB_ANSWER_OFFSET) return "heartbeat DOWN answered";
            return "heartbeat";
        case bsd::CMD_DEBUG: return "debug echo";
        default: std::snprintf(b, sizeof b, "unknown command 0x%02X", cmd); return b;
    }
}

inline Line host_packet(const std::vector<uint8_t>& p) { return {"> " + hex_packet(p, false), decode_host(p)}; }

inline Line raw_input(int pin) {
    char b[64];
    std::snprintf(b, sizeof b, "* raw input %d", kTransIdBase + pin);
    return {b, "pin " + std::to_string(pin) + " transition latch fired"};
}

inline Line rflx(int id, int data) {
    char b[64];
    std::snprintf(b, sizeof b, "* RFLX id %d = %d", id, data);
    return {b, ""};
}

}  // namespace bsdsim
