// Standalone Verilator session runner for brainstem_dio.
//
// Plays a session script (host packets, pin stimulus, waits, expected replies)
// against the core and prints a transcript in the BrainStem Console's style:
//   [  1.234567 ms] > 02:1A,01,00              host -> core
//   [  2.000000 ms] < 02:04,0E,01,F4  pin 4 timer: 500 ticks = 800.0 us
// Script lines (decimal or 0x-hex numbers, times in us/ms/s, '#' comments):
//   2 26 1 0              a host packet: address, then data (the length is inserted)
//   pin 4 high | low      set a pad level
//   pin 4 pulse 800us     invert the pad for that long, then restore it
//   wait 2ms              let time pass
//   expect 2 4 4 14 1 244 the next packet from the core, whole (address, N, data)
//   reset                 pulse rst
// A bad line or a failed expect stops the run with file:line and exit code 1.
//
// Usage: session [--bench CYCLES] [--no-wave] [--wave FILE] [--quiet] SCRIPT
//
// The protocol's numbers and names come from bsd_protocol.h (generated from
// tools/protocol.toml). The core's parameters come from the build: the Makefile passes
// the same values to Verilator (-G) and here (-D), from one set of make variables.

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "Vbrainstem_dio.h"
#include "bsd_protocol.h"
#include "verilated.h"
#if VM_TRACE_FST
#include "verilated_fst_c.h"
using Trace = VerilatedFstC;
#elif VM_TRACE
#include "verilated_vcd_c.h"
using Trace = VerilatedVcdC;
#else
// Built without tracing (the benchmark build): a stand-in that is never opened.
struct Trace {
    void open(const char*) {}
    void dump(uint64_t) {}
    void close() {}
};
#endif

#if !defined(BSD_CLK_HZ) || !defined(BSD_MODULE_ADDR) || !defined(BSD_NUM_PINS) || \
    !defined(BSD_PIN_ID_BASE) || !defined(BSD_TIMER_ID_BASE) || !defined(BSD_TRANS_ID_BASE)
#error "build with make (sim-build): BSD_CLK_HZ, BSD_MODULE_ADDR, BSD_NUM_PINS, BSD_*_ID_BASE = the model's -G values"
#endif

namespace {

// The core's parameters this runner was built for (the same as the model's).
constexpr uint64_t kClkHz = BSD_CLK_HZ;
constexpr int kModuleAddr = BSD_MODULE_ADDR;
constexpr int kNumPins = BSD_NUM_PINS;
constexpr int kPinIdBase = BSD_PIN_ID_BASE;
constexpr int kTimerIdBase = BSD_TIMER_ID_BASE;
constexpr int kTransIdBase = BSD_TRANS_ID_BASE;
static_assert(kNumPins >= 1 && kNumPins <= 64, "NUM_PINS is 1..64");
constexpr double kTickUs = 1e6 / bsd::TICK_HZ;

// A VCD of every clock of a 100 ms wait would take hundreds of MB, so without
// FST the waveform keeps only the clocks within this long after a port event.
constexpr double kVcdWindowS = 200e-6;

// Bounds so that no script can hang the runner.
constexpr double kSendLimitS = 1.0;
constexpr double kExpectLimitS = 0.2;  // above the 104.9 ms timer timeout

struct Fail {
    std::string msg;
};

enum class Op { Send, PinSet, PinPulse, Wait, Expect, Reset };

struct Step {
    Op op;
    int line;
    std::vector<uint8_t> bytes;  // Send: address + data; Expect: whole packet
    int pin = 0;
    int level = 0;
    double seconds = 0;
};

bool parse_int(const std::string& tok, long& out) {
    if (tok.empty()) return false;
    char* end = nullptr;
    errno = 0;
    const bool hex = tok.size() > 2 && tok[0] == '0' && (tok[1] == 'x' || tok[1] == 'X');
    out = std::strtol(tok.c_str(), &end, hex ? 16 : 10);
    return errno == 0 && end && *end == '\0' && (hex || std::isdigit((unsigned char)tok[0]));
}

bool parse_byte(const std::string& tok, uint8_t& out) {
    long v;
    if (!parse_int(tok, v) || v < 0 || v > 255) return false;
    out = static_cast<uint8_t>(v);
    return true;
}

bool parse_time(const std::string& tok, double& seconds) {
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

std::vector<Step> parse_script(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw Fail{path + ": cannot open the script"};
    std::vector<Step> steps;
    std::string text;
    int line = 0;
    auto fail = [&](const std::string& m) { return Fail{path + ":" + std::to_string(line) + ": " + m}; };
    while (std::getline(in, text)) {
        ++line;
        const size_t hash = text.find('#');
        if (hash != std::string::npos) text.resize(hash);
        std::istringstream ss(text);
        std::vector<std::string> tok;
        for (std::string t; ss >> t;) tok.push_back(t);
        if (tok.empty()) continue;
        Step st{};
        st.line = line;
        const std::string& kw = tok[0];
        if (kw == "pin") {
            long pin;
            if (tok.size() < 3) throw fail("'pin' needs a pin number and high, low or pulse");
            if (!parse_int(tok[1], pin) || pin < 0 || pin >= kNumPins)
                throw fail("bad pin number '" + tok[1] + "' (0.." + std::to_string(kNumPins - 1) + ")");
            st.pin = static_cast<int>(pin);
            if ((tok[2] == "high" || tok[2] == "low") && tok.size() == 3) {
                st.op = Op::PinSet;
                st.level = tok[2] == "high";
            } else if (tok[2] == "pulse" && tok.size() == 4) {
                st.op = Op::PinPulse;
                if (!parse_time(tok[3], st.seconds)) throw fail("bad time '" + tok[3] + "' (e.g. 800us, 2ms, 1s)");
            } else {
                throw fail("expected 'pin N high', 'pin N low' or 'pin N pulse TIME'");
            }
        } else if (kw == "wait") {
            st.op = Op::Wait;
            if (tok.size() != 2 || !parse_time(tok[1], st.seconds))
                throw fail("expected 'wait TIME' (e.g. wait 2ms)");
        } else if (kw == "expect") {
            st.op = Op::Expect;
            if (tok.size() < 3) throw fail("'expect' needs a whole packet: address, N, data");
            for (size_t i = 1; i < tok.size(); ++i) {
                uint8_t b;
                if (!parse_byte(tok[i], b)) throw fail("bad byte '" + tok[i] + "' (0..255)");
                st.bytes.push_back(b);
            }
            if (st.bytes[1] != st.bytes.size() - 2)
                throw fail("expect: N is " + std::to_string(st.bytes[1]) + " but " +
                           std::to_string(st.bytes.size() - 2) + " data bytes follow");
        } else if (kw == "reset") {
            if (tok.size() != 1) throw fail("'reset' takes no argument");
            st.op = Op::Reset;
        } else if (std::isdigit((unsigned char)kw[0])) {
            st.op = Op::Send;
            for (const auto& t : tok) {
                uint8_t b;
                if (!parse_byte(t, b)) throw fail("bad byte '" + t + "' (0..255)");
                st.bytes.push_back(b);
            }
        } else {
            throw fail("unknown keyword '" + kw + "'");
        }
        steps.push_back(st);
    }
    return steps;
}

const char* message_name(uint8_t code) {
    const char* text = bsd::message_text(code);
    return text ? text : "message";
}

std::string hex_packet(const std::vector<uint8_t>& p, bool with_len) {
    // Console style: address, then the data bytes (with_len adds N).
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

std::string decode_cfg(uint8_t c) {
    std::string s = (c & bsd::DIGCFG_IODIR) ? "input" : "output";
    if (c & bsd::DIGCFG_ENA) s += std::string(", latch on ") + ((c & bsd::DIGCFG_TRG) ? "0->1" : "1->0");
    if (c & bsd::DIGCFG_TMODE) s += std::string(", width timer of ") + ((c & bsd::DIGCFG_TSTATE) ? "high" : "low");
    else if (c & bsd::DIGCFG_TSTATE) s += ", edge timer to high";
    if (c & bsd::DIGCFG_FIXED) s += ", fixed";
    return s;
}

std::string decode(const std::vector<uint8_t>& p) {
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
    return "";
}

class Session {
  public:
    Session(VerilatedContext* ctx, const char* wave, bool quiet)
        : top_(new Vbrainstem_dio{ctx}), quiet_(quiet) {
#if VM_TRACE
        if (wave) {
            ctx->traceEverOn(true);
            trace_.reset(new Trace);
            top_->trace(trace_.get(), 99);
            trace_->open(wave);
        }
#else
        (void)ctx;
        if (wave) std::fprintf(stderr, "note: built without tracing, no waveform\n");
#endif
        top_->pin_i = 0;
        top_->m_axis_tready = 1;
        reset();
    }
    ~Session() {
        if (trace_) trace_->close();
        top_->final();
    }

    uint64_t cycles() const { return cycle_; }
    double now() const { return static_cast<double>(cycle_) / kClkHz; }

    void reset() {
        txq_.clear();
        out_.clear();
        cur_.clear();
        top_->rst = 1;
        for (int i = 0; i < 4; ++i) clock();
        top_->rst = 0;
        log("reset", "");
    }

    void run_for(double seconds) {
        const uint64_t end = cycle_ + static_cast<uint64_t>(seconds * kClkHz + 0.5);
        while (cycle_ < end) clock();
    }

    void send(const std::vector<uint8_t>& addr_and_data) {
        std::vector<uint8_t> pkt{addr_and_data[0], static_cast<uint8_t>(addr_and_data.size() - 1)};
        pkt.insert(pkt.end(), addr_and_data.begin() + 1, addr_and_data.end());
        for (uint8_t b : pkt) txq_.push_back(b);
        const uint64_t limit = cycle_ + static_cast<uint64_t>(kSendLimitS * kClkHz);
        while (!txq_.empty()) {
            if (cycle_ >= limit) throw Fail{"the core did not take the packet within 1 s"};
            clock();
        }
        log("> " + hex_packet(pkt, false), "");
    }

    void set_pin(int pin, int level) {
        last_event_ = cycle_;
        if (level) top_->pin_i |= uint64_t{1} << pin;  // pin_i is 8 to 64 bits wide
        else top_->pin_i &= ~(uint64_t{1} << pin);
    }
    int pin(int p) const { return (top_->pin_i >> p) & 1; }

    std::vector<uint8_t> next_packet() {
        const uint64_t limit = cycle_ + static_cast<uint64_t>(kExpectLimitS * kClkHz);
        while (out_.empty()) {
            if (cycle_ >= limit) throw Fail{"no packet from the core within 200 ms"};
            clock();
        }
        std::vector<uint8_t> p = out_.front();
        out_.pop_front();
        return p;
    }

    // Busy traffic for the benchmark: back-to-back configuration, reads and
    // timer starts while two pins toggle, for `n` clock cycles.
    void bench(uint64_t n) {
        using namespace bsd;
        constexpr uint8_t A = kModuleAddr, H = DEVCODE_HOST;
        static const std::vector<std::vector<uint8_t>> cmds = {
            {A, CMD_DIG_CFG, 3, 0x19}, {A, CMD_PTIME_RD, H | 3}, {A, CMD_DIG_IO, H | 0},
            {A, CMD_DIG_CFG, 4, 0x01}, {A, CMD_PTIME_RD, H | 4}, {A, CMD_DIG_RST, 2},
            {A, CMD_DIG_CFG, 1, 0x01}, {A, CMD_PTIME_RD, H | 1}};
        const uint64_t end = cycle_ + n;
        size_t k = 0;
        while (cycle_ < end) {
            if (txq_.empty()) {
                const auto& c = cmds[k++ % cmds.size()];
                txq_.push_back(c[0]);
                txq_.push_back(static_cast<uint8_t>(c.size() - 1));
                for (size_t i = 1; i < c.size(); ++i) txq_.push_back(c[i]);
            }
            if ((cycle_ & 1023) == 0) top_->pin_i ^= 0x18;  // pins 3 and 4 toggle
            clock();
            out_.clear();
        }
    }

    void log(const std::string& what, const std::string& meaning) {
        if (quiet_) return;
        std::printf("[%12.6f ms] %-28s %s\n", now() * 1e3, what.c_str(), meaning.c_str());
    }

  private:
    void clock() {
        const bool tx_valid = !txq_.empty();
        top_->s_axis_tvalid = tx_valid;
        top_->s_axis_tdata = tx_valid ? txq_.front() : 0;
        top_->clk = 0;
        top_->eval();
        const bool dump = trace_ && (VM_TRACE_FST || cycle_ - last_event_ < window_);
        if (dump) trace_->dump(2 * cycle_);
        // Handshakes and strobes are sampled before the rising edge.
        const bool s_hs = tx_valid && top_->s_axis_tready;
        if (s_hs || top_->raw_trans || top_->rflx_valid || top_->rst) last_event_ = cycle_;
        if (top_->m_axis_tvalid && top_->m_axis_tready) {
            last_event_ = cycle_;
            cur_.push_back(top_->m_axis_tdata);
            if (top_->m_axis_tlast) received();
        }
        if (top_->raw_trans && !quiet_) raw_inputs(top_->raw_trans);
        if (top_->rflx_valid && !quiet_) {
            char b[64];
            std::snprintf(b, sizeof b, "* RFLX id %d = %d", top_->rflx_id, top_->rflx_data);
            log(b, "");
        }
        top_->clk = 1;
        top_->eval();
        if (dump) trace_->dump(2 * cycle_ + 1);
        ++cycle_;
        if (s_hs) txq_.pop_front();
    }

    void received() {
        std::vector<uint8_t> p;
        p.swap(cur_);
        if (quiet_) {
            out_.push_back(std::move(p));
            return;
        }
        if (p.size() >= 4 && p[1] == bsd::MSG_N && p[2] == bsd::CMD_MSG) {
            char b[48];
            std::snprintf(b, sizeof b, "< %d:%s", p[0], message_name(p[3]));
            log(b, "(" + hex_packet(p, false) + ")");
        } else {
            log("< " + hex_packet(p, false), decode(p));
        }
        out_.push_back(p);
    }

    void raw_inputs(uint64_t bits) {
        for (int p = 0; p < kNumPins; ++p) {
            if (bits & (uint64_t{1} << p)) {
                char b[64];
                std::snprintf(b, sizeof b, "* raw input %d", kTransIdBase + p);
                log(b, "pin " + std::to_string(p) + " transition latch fired");
            }
        }
    }

    std::unique_ptr<Vbrainstem_dio> top_;
    std::unique_ptr<Trace> trace_;
    bool quiet_;
    uint64_t cycle_ = 0;
    uint64_t last_event_ = 0;
    const uint64_t window_ = static_cast<uint64_t>(kVcdWindowS * kClkHz);
    std::deque<uint8_t> txq_;
    std::vector<uint8_t> cur_;
    std::deque<std::vector<uint8_t>> out_;
};

void play(Session& s, const std::vector<Step>& steps, const std::string& path) {
    for (const Step& st : steps) {
        try {
            switch (st.op) {
                case Op::Send: s.send(st.bytes); break;
                case Op::PinSet:
                    s.set_pin(st.pin, st.level);
                    s.log("pin " + std::to_string(st.pin) + (st.level ? " high" : " low"), "");
                    break;
                case Op::PinPulse: {
                    const int before = s.pin(st.pin);
                    s.set_pin(st.pin, !before);
                    char b[64];
                    std::snprintf(b, sizeof b, "pin %d pulse %s %.1f us", st.pin, before ? "low" : "high",
                                  st.seconds * 1e6);
                    s.log(b, "");
                    s.run_for(st.seconds);
                    s.set_pin(st.pin, before);
                    break;
                }
                case Op::Wait: s.run_for(st.seconds); break;
                case Op::Reset: s.reset(); break;
                case Op::Expect: {
                    const std::vector<uint8_t> got = s.next_packet();
                    if (got != st.bytes)
                        throw Fail{"expected " + hex_packet(st.bytes, true) + " but the core sent " +
                                   hex_packet(got, true)};
                    break;
                }
            }
        } catch (const Fail& f) {
            throw Fail{path + ":" + std::to_string(st.line) + ": " + f.msg};
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    const char* script = nullptr;
    std::string wave = VM_TRACE_FST ? "sim/build/session.fst" : "sim/build/session.vcd";
    bool use_wave = true, quiet = false;
    uint64_t bench_cycles = 0;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--no-wave")) use_wave = false;
        else if (!std::strcmp(argv[i], "--quiet")) quiet = true;
        else if (!std::strcmp(argv[i], "--wave") && i + 1 < argc) wave = argv[++i];
        else if (!std::strcmp(argv[i], "--bench") && i + 1 < argc) bench_cycles = std::strtoull(argv[++i], nullptr, 10);
        else if (argv[i][0] == '+') continue;  // Verilator plusargs
        else script = argv[i];
    }
    auto ctx = std::make_unique<VerilatedContext>();
    ctx->commandArgs(argc, argv);
    try {
        if (bench_cycles) {
            Session s(ctx.get(), nullptr, true);
            s.bench(1000);  // warm up
            const uint64_t start = s.cycles();
            const auto t0 = std::chrono::steady_clock::now();
            s.bench(bench_cycles);
            const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            std::printf("cycles %" PRIu64 " seconds %.3f cycles_per_second %.0f\n", s.cycles() - start, dt,
                        (s.cycles() - start) / dt);
            return 0;
        }
        if (!script) {
            std::fprintf(stderr, "usage: %s [--no-wave] [--wave FILE] [--quiet] SCRIPT | --bench CYCLES\n", argv[0]);
            return 2;
        }
        const std::vector<Step> steps = parse_script(script);
        std::printf("brainstem_dio session: %s, clk %.3f MHz, module %d\n", script, kClkHz / 1e6, kModuleAddr);
        Session s(ctx.get(), use_wave ? wave.c_str() : nullptr, quiet);
        play(s, steps, script);
        std::printf("done: %.6f s simulated, %" PRIu64 " cycles%s%s\n", s.now(), s.cycles(),
                    use_wave ? ", waveform " : "", use_wave ? wave.c_str() : "");
    } catch (const Fail& f) {
        std::fflush(stdout);
        std::fprintf(stderr, "error: %s\n", f.msg.c_str());
        return 1;
    }
    return 0;
}
