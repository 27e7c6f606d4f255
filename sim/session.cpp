// SPDX-License-Identifier: Apache-2.0
// Standalone Verilator session runner for brainstem_dio.
//
// Plays a session script (host packets, pin stimulus, waits, expected replies)
// against the core and prints a transcript in the BrainStem Console's style:
//   [  1.234567 ms] > 02:1A,01,00              host -> core
//   [  2.000000 ms] < 02:04,0E,01,F4  pin 4 timer: 500 ticks = 800.0 us
// Script lines (decimal or 0x-hex numbers, times in us/ms/s, '#' comments; the parser is
// sim/script.h, shared with the virtual module):
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
// The transcript's decoder is sim/transcript.h (shared with the virtual module). The
// protocol's numbers and names come from bsd_protocol.h (generated from
// tools/protocol.toml). The core's parameters come from the build: the Makefile passes
// the same values to Verilator (-G) and here (-D), from one set of make variables.

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "Vbrainstem_dio.h"
#include "Vbrainstem_dio___024root.h"
#include "fast_eval.h"
#include "bsd_protocol.h"
#include "script.h"
#include "transcript.h"
#include "verilated.h"
#include "trace.h"

BSD_FAST_EVAL(Vbrainstem_dio)

namespace {

using namespace bsdsim;

// A packet's bytes on the wire from the script's form: the address, N (the data bytes' count),
// then the data.
std::vector<uint8_t> framed(const std::vector<uint8_t>& addr_and_data) {
    std::vector<uint8_t> pkt{addr_and_data[0], static_cast<uint8_t>(addr_and_data.size() - 1)};
    pkt.insert(pkt.end(), addr_and_data.begin() + 1, addr_and_data.end());
    return pkt;
}

// The bytes waiting for s_axis, read through a pointer: a packet of send()'s, copied in, or
// the benchmark's command stream, which stays where it is (a std::deque's front and pop_front
// and a push per byte cost the benchmark about 20 instructions a clock).
class ByteQueue {
  public:
    bool empty() const { return p_ == end_; }
    uint8_t front() const { return *p_; }
    void pop_front() { ++p_; }
    void clear() { p_ = end_ = nullptr; }
    // Only when empty: the bytes, copied.
    void assign(const std::vector<uint8_t>& bytes) {
        own_ = bytes;
        p_ = own_.data();
        end_ = p_ + own_.size();
    }
    // Only when empty: the bytes from b to e, which the caller keeps until they are taken.
    void view(const uint8_t* b, const uint8_t* e) {
        p_ = b;
        end_ = e;
    }
    const uint8_t* pos() const { return p_; }

  private:
    std::vector<uint8_t> own_;
    const uint8_t* p_ = nullptr;
    const uint8_t* end_ = nullptr;
};

// A VCD of every clock of a 100 ms wait would take hundreds of MB, so without
// FST the waveform keeps only the clocks within this long after a port event.
constexpr double kVcdWindowS = 200e-6;

// Bounds so that no script can hang the runner.
constexpr double kSendLimitS = 1.0;
constexpr double kExpectLimitS = 0.2;  // above the 104.9 ms timer timeout

class Session {
  public:
    Session(VerilatedContext* ctx, const char* wave, bool quiet)
        : top_(new Vbrainstem_dio{ctx}), r_(*top_->rootp), quiet_(quiet), watch_(!quiet || wave) {
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
        top_->clk = 0;
        top_->eval();  // the public one first: initial blocks (sim/fast_eval.h)
        sync_inputs();
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
        settle(*top_);  // s_axis_tready follows rst without a clock
        sync_inputs();
        for (int i = 0; i < 4; ++i) clock();
        top_->rst = 0;
        settle(*top_);
        sync_inputs();
        log("reset", "");
    }

    void run_for(double seconds) {
        const uint64_t end = cycle_ + static_cast<uint64_t>(seconds * kClkHz + 0.5);
        while (cycle_ < end) clock();
    }

    void send(const std::vector<uint8_t>& addr_and_data) {
        const std::vector<uint8_t> pkt = framed(addr_and_data);
        txq_.assign(pkt);  // empty: the last send() or reset() emptied it
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
        // The packets back to back, as one stream sent again each time it is taken: the
        // same bytes on the same clocks as one packet queued whenever the last has gone.
        static const std::vector<uint8_t> stream = [] {
            std::vector<uint8_t> v;
            for (const auto& c : cmds) {
                const std::vector<uint8_t> pkt = framed(c);
                v.insert(v.end(), pkt.begin(), pkt.end());
            }
            return v;
        }();
        // The benchmark's own clock loop, not clock(): no transcript, no waveform, the output
        // bytes counted, not kept (the benchmark drops its packets unread), and its state in
        // locals, which stay in registers across the model's call where members would be
        // loaded and stored again each clock (about 25 instructions a clock of ~55).
        Vbrainstem_dio___024root& r = r_;
        const uint8_t* const first = stream.data();
        const uint8_t* const last = first + stream.size();
        const uint8_t* p = txq_.empty() ? first : txq_.pos();  // (the warm-up's place)
        uint64_t c = cycle_;
        const uint64_t end = c + n;
        uint64_t out = 0;
        // One clock: the byte on offer, the handshakes sampled before the rising edge
        // (sim/fast_eval.h), as clock() does.
        auto tick = [&](bool in_changed) [[gnu::always_inline]] {
            r.s_axis_tdata = *p;
            const bool s_hs = r.s_axis_tready;
            out += r.m_axis_tvalid & r.m_axis_tready;
            posedge(r, in_changed);
            if (s_hs && ++p == last) p = first;
        };
        r.s_axis_tvalid = 1;  // the stream never runs dry: sent again as soon as it is taken
        bool in_changed = inputs_.changed(r.rst, r.m_axis_tready, r.pin_i);
        while (c < end) {
            if ((c & 1023) == 0) {  // pins 3 and 4 toggle
                r.pin_i ^= 0x18;
                in_changed = true;
            }
            // The first clock up to the next toggle, then the others, which change no input
            // that the input logic reads.
            const uint64_t stop = std::min(end, (c | 1023) + 1);
            tick(in_changed);
            for (++c; c < stop; ++c) tick(false);
            in_changed = false;
        }
        cycle_ = c;
        bench_bytes_ += out;
        txq_.view(p, last);  // the stream's rest: the next bench() goes on from here
        inputs_.sync(r.rst, r.m_axis_tready, r.pin_i);
    }

    // The core's bytes the benchmark has counted.
    uint64_t bench_bytes() const { return bench_bytes_; }

    void log(const std::string& what, const std::string& meaning) {
        if (quiet_) return;
        print_line(now(), what, meaning);
    }

  private:
    // The model's ports are read and written on its root (r_), where they live: the top's
    // members are references to them, one load more each.
    [[gnu::always_inline]] inline void clock() {
        // (a local reference: the byte stores below may alias *this, after each of which a
        // member reference would be loaded again)
        Vbrainstem_dio___024root& r = r_;
        const bool tx_valid = !txq_.empty();
        r.s_axis_tvalid = tx_valid;
        r.s_axis_tdata = tx_valid ? txq_.front() : 0;
        const bool dump = trace_ && (VM_TRACE_FST || cycle_ - last_event_ < window_);
        if (dump) {  // the waveform's falling edge; the model has no logic on it
            r.clk = 0;
            settle(*top_);
            trace_->dump(2 * cycle_);
        }
        // Handshakes and strobes are sampled before the rising edge: the outputs of the last
        // one (sim/fast_eval.h).
        const bool s_hs = tx_valid && r.s_axis_tready;
        if (r.m_axis_tvalid && r.m_axis_tready) {
            last_event_ = cycle_;
            cur_.push_back(r.m_axis_tdata);
            if (r.m_axis_tlast) received();
        }
        if (watch_) {  // the transcript's strobes, and the VCD's window
            if (s_hs || r.raw_trans || r.rflx_valid || r.rst) last_event_ = cycle_;
            if (r.raw_trans && !quiet_) raw_inputs(r.raw_trans);
            if (r.rflx_valid && !quiet_) {
                const Line l = rflx(r.rflx_id, r.rflx_data);
                log(l.what, l.meaning);
            }
        }
        if (dump) {  // through the public eval(): it marks the activity the waveform records
            r.clk = 1;
            top_->eval();
            sync_inputs();
            trace_->dump(2 * cycle_ + 1);
        } else {
            posedge(r, inputs_.changed(r.rst, r.m_axis_tready, r.pin_i));
        }
        ++cycle_;
        if (s_hs) txq_.pop_front();
    }

    // After a public eval(): the inputs its input logic ran with (sim/fast_eval.h).
    void sync_inputs() {
        inputs_.sync(r_.rst, r_.m_axis_tready, r_.pin_i);
    }

    void received() {
        out_.push_back(cur_);  // a copy: cur_ keeps its capacity for the next packet
        cur_.clear();
        if (quiet_) return;
        const Line l = core_packet(out_.back());
        log(l.what, l.meaning);
    }

    void raw_inputs(uint64_t bits) {
        for (int p = 0; p < kNumPins; ++p) {
            if (bits & (uint64_t{1} << p)) {
                const Line l = raw_input(p);
                log(l.what, l.meaning);
            }
        }
    }

    std::unique_ptr<Vbrainstem_dio> top_;
    Vbrainstem_dio___024root& r_;
    std::unique_ptr<Trace> trace_;
    // The inputs the model's input logic may read, as sync_inputs() and clock() pass them: not
    // s_axis_tdata and s_axis_tvalid, which the parser reads only in its clocked logic (the
    // Makefile's SESSION_UNWATCHED: the build stops if the input logic reads them).
    Inputs<CData, CData, std::remove_reference_t<decltype(Vbrainstem_dio::pin_i)>> inputs_;
    bool quiet_;
    const bool watch_;     // a transcript or a waveform to write
    uint64_t bench_bytes_ = 0;
    uint64_t cycle_ = 0;
    uint64_t last_event_ = 0;
    const uint64_t window_ = static_cast<uint64_t>(kVcdWindowS * kClkHz);
    ByteQueue txq_;
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
            const uint64_t start = s.cycles(), bytes = s.bench_bytes();
            const auto t0 = std::chrono::steady_clock::now();
            s.bench(bench_cycles);
            const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            std::printf("cycles %" PRIu64 " seconds %.3f cycles_per_second %.0f bytes_out %" PRIu64 "\n",
                        s.cycles() - start, dt, (s.cycles() - start) / dt, s.bench_bytes() - bytes);
            return 0;
        }
        if (!script) {
            std::fprintf(stderr, "usage: %s [--no-wave] [--wave FILE] [--quiet] SCRIPT | --bench CYCLES\n", argv[0]);
            return 2;
        }
        const std::vector<Step> steps = parse_script(script, kNumPins);
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
