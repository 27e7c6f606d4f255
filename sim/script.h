// SPDX-License-Identifier: Apache-2.0
// Session-script lines, shared by the session runner (sim/session.cpp, a script file) and the
// virtual module (sim/virtual.cpp, standard input). Numbers are decimal or 0x-hex, times carry
// a unit (ns, us, ms, s), '#' starts a comment:
//   2 26 1 0              a host packet: address, then data (the length is inserted)   [script]
//   pin 4 high | low      set a pad level
//   pin 4 pulse 800us     invert the pad for that long, then restore it
//   wait 2ms              let time pass
//   expect 2 4 4 14 1 244 the next packet from the core, whole (address, N, data)      [script]
//   reset                 pulse rst
//   noise 3 2             send these bytes to the host between packets                [stdin]
//   ber 1e-3              flip each bit on both serial lines with this probability     [stdin]
//   stats                 print the bits flipped so far per line                       [stdin]
//   quit                  stop                                                        [stdin]
// The parser knows nothing of the core but its pin count; a bad line throws Fail with the
// message, and the caller adds where the line came from ("file:line: ", "stdin:line: ").
#pragma once

#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace bsdsim {

struct Fail {
    std::string msg;
};

enum class Op { Send, PinSet, PinPulse, Wait, Expect, Reset, Noise, Quit, Ber, Stats };

// Which lines a reader takes: a session script (make sim) or the virtual module's stdin,
// where packets come from the host on the port instead and `noise` and `quit` are added.
enum class Dialect { Script, Stdin };

struct Step {
    Op op;
    int line;
    std::vector<uint8_t> bytes;  // Send: address + data; Expect: whole packet; Noise: the bytes
    int pin = 0;
    int level = 0;
    double seconds = 0;
    double ber = 0;  // Ber: the probability
};

inline bool parse_int(const std::string& tok, long& out) {
    if (tok.empty()) return false;
    char* end = nullptr;
    errno = 0;
    const bool hex = tok.size() > 2 && tok[0] == '0' && (tok[1] == 'x' || tok[1] == 'X');
    out = std::strtol(tok.c_str(), &end, hex ? 16 : 10);
    return errno == 0 && end && *end == '\0' && (hex || std::isdigit((unsigned char)tok[0]));
}

inline bool parse_byte(const std::string& tok, uint8_t& out) {
    long v;
    if (!parse_int(tok, v) || v < 0 || v > 255) return false;
    out = static_cast<uint8_t>(v);
    return true;
}

inline bool parse_time(const std::string& tok, double& seconds) {
    static const struct {
        const char* unit;
        double scale;
    } units[] = {{"us", 1e-6}, {"ms", 1e-3}, {"ns", 1e-9}, {"s", 1.0}};
    for (const auto& u : units) {
        const size_t n = std::strlen(u.unit);
        if (tok.size() > n && tok.compare(tok.size() - n, n, u.unit) == 0) {
            const std::string num = tok.substr(0, tok.size() - n);
            char* end = nullptr;
            errno = 0;
            const double v = std::strtod(num.c_str(), &end);
            if (errno || !end || *end != '\0' || num.empty() || v < 0 || v > 100.0 / u.scale)
                return false;
            seconds = v * u.scale;
            return true;
        }
    }
    return false;
}

// A bit error rate: a probability from 0 to 1, decimal or with an exponent (1e-3, 0.001).
inline bool parse_ber(const std::string& tok, double& p) {
    if (tok.empty()) return false;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(tok.c_str(), &end);
    // v == v and the range test refuse nan and inf; strtod's hex floats and leading blanks too.
    if (errno || !end || *end != '\0' || !(v >= 0.0 && v <= 1.0) || std::isspace((unsigned char)tok[0]) ||
        tok.find_first_of("xXnN") != std::string::npos)
        return false;
    p = v;
    return true;
}

constexpr const char* kBerHelp = "a bit error rate from 0 to 1, e.g. 1e-3";

// One line of text -> its step. Returns false for a blank or comment-only line; throws
// Fail{message} for a bad one.
inline bool parse_line(const std::string& raw, int line, int num_pins, Dialect dialect, Step& st) {
    std::string text = raw;
    const size_t hash = text.find('#');
    if (hash != std::string::npos) text.resize(hash);
    std::istringstream ss(text);
    std::vector<std::string> tok;
    for (std::string t; ss >> t;) tok.push_back(t);
    if (tok.empty()) return false;
    st = Step{};
    st.line = line;
    const bool stdin_lines = dialect == Dialect::Stdin;
    const char* stdin_takes = " (standard input takes pin, wait, reset, noise, ber, stats and quit)";
    const std::string& kw = tok[0];
    if (kw == "pin") {
        long pin;
        if (tok.size() < 3) throw Fail{"'pin' needs a pin number and high, low or pulse"};
        if (!parse_int(tok[1], pin) || pin < 0 || pin >= num_pins)
            throw Fail{"bad pin number '" + tok[1] + "' (0.." + std::to_string(num_pins - 1) + ")"};
        st.pin = static_cast<int>(pin);
        if ((tok[2] == "high" || tok[2] == "low") && tok.size() == 3) {
            st.op = Op::PinSet;
            st.level = tok[2] == "high";
        } else if (tok[2] == "pulse" && tok.size() == 4) {
            st.op = Op::PinPulse;
            if (!parse_time(tok[3], st.seconds)) throw Fail{"bad time '" + tok[3] + "' (e.g. 800us, 2ms, 1s)"};
        } else {
            throw Fail{"expected 'pin N high', 'pin N low' or 'pin N pulse TIME'"};
        }
    } else if (kw == "wait") {
        st.op = Op::Wait;
        if (tok.size() != 2 || !parse_time(tok[1], st.seconds))
            throw Fail{"expected 'wait TIME' (e.g. wait 2ms)"};
    } else if (kw == "expect" && !stdin_lines) {
        st.op = Op::Expect;
        if (tok.size() < 3) throw Fail{"'expect' needs a whole packet: address, N, data"};
        for (size_t i = 1; i < tok.size(); ++i) {
            uint8_t b;
            if (!parse_byte(tok[i], b)) throw Fail{"bad byte '" + tok[i] + "' (0..255)"};
            st.bytes.push_back(b);
        }
        if (st.bytes[1] != st.bytes.size() - 2)
            throw Fail{"expect: N is " + std::to_string(st.bytes[1]) + " but " +
                       std::to_string(st.bytes.size() - 2) + " data bytes follow"};
    } else if (kw == "expect") {
        throw Fail{std::string("'expect' belongs in make sim scripts; here the host reads the replies") +
                   stdin_takes};
    } else if (kw == "reset") {
        if (tok.size() != 1) throw Fail{"'reset' takes no argument"};
        st.op = Op::Reset;
    } else if (kw == "noise" && stdin_lines) {
        st.op = Op::Noise;
        if (tok.size() < 2) throw Fail{"'noise' needs the bytes to send (e.g. noise 3 2, noise 0x03 0x02)"};
        for (size_t i = 1; i < tok.size(); ++i) {
            uint8_t b;
            if (!parse_byte(tok[i], b)) throw Fail{"bad byte '" + tok[i] + "' (0..255)"};
            st.bytes.push_back(b);
        }
    } else if (kw == "ber" && stdin_lines) {
        st.op = Op::Ber;
        if (tok.size() != 2) throw Fail{std::string("expected 'ber P' (") + kBerHelp + ")"};
        if (!parse_ber(tok[1], st.ber)) throw Fail{"bad bit error rate '" + tok[1] + "' (" + kBerHelp + ")"};
    } else if (kw == "stats" && stdin_lines) {
        if (tok.size() != 1) throw Fail{"'stats' takes no argument"};
        st.op = Op::Stats;
    } else if (kw == "quit" && stdin_lines) {
        if (tok.size() != 1) throw Fail{"'quit' takes no argument"};
        st.op = Op::Quit;
    } else if (std::isdigit((unsigned char)kw[0]) && !stdin_lines) {
        st.op = Op::Send;
        for (const auto& t : tok) {
            uint8_t b;
            if (!parse_byte(t, b)) throw Fail{"bad byte '" + t + "' (0..255)"};
            st.bytes.push_back(b);
        }
    } else if (std::isdigit((unsigned char)kw[0])) {
        throw Fail{std::string("packets come from the host through the port, not from here") + stdin_takes};
    } else {
        throw Fail{"unknown keyword '" + kw + "'" + (stdin_lines ? stdin_takes : "")};
    }
    return true;
}

// A whole script file (make sim). Errors carry "path:line: ".
inline std::vector<Step> parse_script(const std::string& path, int num_pins) {
    std::ifstream in(path);
    if (!in) throw Fail{path + ": cannot open the script"};
    std::vector<Step> steps;
    std::string text;
    int line = 0;
    while (std::getline(in, text)) {
        ++line;
        Step st;
        try {
            if (!parse_line(text, line, num_pins, Dialect::Script, st)) continue;
        } catch (const Fail& f) {
            throw Fail{path + ":" + std::to_string(line) + ": " + f.msg};
        }
        steps.push_back(st);
    }
    return steps;
}

}  // namespace bsdsim
