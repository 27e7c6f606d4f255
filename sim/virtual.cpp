// SPDX-License-Identifier: Apache-2.0
// The virtual module: brainstem_dio_uart (the FPGA board's RTL: UART, RX FIFO, cmdQOverflow,
// heartbeat) simulated by Verilator behind a pseudo-terminal, in step with the wall clock, so
// that an unmodified serial host program can open the pty like a real module's serial port.
//
//   virtual [--link PATH] [--wave FILE] [--ber P] [--seed N]
//                                          run; print "port: /dev/pts/N"; PATH -> the pty
//                                          (--wave: only in make's WAVES=1 build, traced)
//   virtual --bench SECONDS                run unpaced for SECONDS of wall time with a busy
//                                          host, print the ratio of simulated to real time
//
// The port. The pty is raw (cfmakeraw, set once on the slave when it is made; it persists
// while this program holds the master) and binary-transparent. The host's baud setting has no
// effect: bytes cross the simulated serial line at BAUD, bit by bit (rx driven from the bytes
// the host writes, tx decoded into the bytes it reads). This program does not keep the slave
// open, so the master tells whether a host has it: read() on the master fails with EIO while
// no process has the slave open and with EAGAIN (or returns data) while one does. Bytes the
// core sends while no host has the port open are dropped (the transcript marks them lost), as
// on a real serial line; when the host closes, what it had not read is flushed (TCOFLUSH).
// The host's bytes are read as they arrive and queued for the line, so a host may write
// faster than BAUD (they leave at BAUD, as from its own UART's buffer). A host that stops
// reading loses the core's bytes that no longer fit in the pty's buffer (stderr says so).
//
// Pacing. The model runs in chunks of at most 1 ms of simulated time, never past the wall
// clock (steady_clock) since start; when ahead it sleeps in ppoll on the pty and stdin.
// Once a second it checks: when it is behind by more than 50 ms and ran slower than real
// time over that second, it prints "behind real time: x0.43" (simulated seconds per wall
// second over that second) on stderr, with ", stalled 0.153 s" when the loop did not run for
// more than 50 ms in that second (then the line comes even if the lag was made up). A lag
// beyond 100 ms is forgiven (the origin moves), so that a stall is not followed by a long
// sprint.
//
// Standard input takes the session-script lines of make sim (sim/script.h): pin N high|low,
// pin N pulse TIME, wait TIME, reset; and noise BYTES (sent to the host at the next packet
// boundary of the core's output), quit. They run in order; wait and pulse hold the lines after
// them for that much simulated time. Standard output is the Console-style transcript
// (sim/transcript.h) of both directions, pad changes, raw_trans, RFLX strobes, link_up, and
// the host opening and closing the port. EOF (after the lines before it have run), quit,
// SIGINT, SIGTERM and SIGHUP end the run cleanly (exit 0) and remove the link. A bad line,
// an unknown option or a pty that cannot be made: a message on stderr and exit 1 (2 for usage).
//
// Line noise (--ber P, the stdin line `ber P`): each bit of a frame on either line (start,
// data and stop bits; not the idle line between frames) is inverted with probability P. The
// rx line is driven inverted for that bit; on the tx line the host's UART (a second decoder
// here, the one whose bytes go to the pty) sees the core's bit inverted, while the transcript
// decodes what the core really sent. So the transcript shows both sides as they were meant,
// and a line `* noise rx 1A  flipped d3 stop [bits 1200 1209]` per byte that was hit (the
// bits' positions count every bit on that line since start). Each line has its own
// generator from the seed (printed at start; --seed repeats it), drawn once per bit while P
// is not 0: the same seed and the same bytes flip the same bits. `stats` prints the counts;
// so does the end of the run. A host UART that sees a 0 stop bit still passes the byte on,
// as Linux does without INPCK. A bad `ber` line is refused on stderr and the run goes on with
// the rate it had (a mistyped rate should not end a long soak); other bad lines end it.
//
// Pads: pin_i of a pin is its pin_o while pin_oe is 1, else the level set from stdin; the
// levels start high, as the board's pull-ups make them.

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/file.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <deque>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "Vbrainstem_dio_uart.h"
#include "Vbrainstem_dio_uart___024root.h"
#include "fast_eval.h"
#include "bsd_protocol.h"
#include "script.h"
#include "transcript.h"
#include "verilated.h"
#include "trace.h"

#if !defined(BSD_BAUD) || !defined(BSD_HB_RATE)
#error "build with make (virtual-build): BSD_BAUD and BSD_HB_RATE = the model's -G values"
#endif

BSD_FAST_EVAL(Vbrainstem_dio_uart)

namespace {

using namespace bsdsim;

constexpr uint64_t kBaud = BSD_BAUD;
constexpr int kHbRate = BSD_HB_RATE;
constexpr uint64_t kDiv = (kClkHz + kBaud / 2) / kBaud;  // clocks per bit, as uart_rx/uart_tx
static_assert(kDiv >= 8, "CLK_HZ / BAUD must be at least 8 (uart_rx)");
constexpr uint64_t kChunk = kClkHz >= 1000 ? kClkHz / 1000 : 1;  // 1 ms of simulated time
constexpr uint64_t kNever = UINT64_MAX;
constexpr double kRxTimeoutS = bsd::DEFAULT_RX_TIMEOUT_US * 1e-6;
constexpr double kBehindS = 0.05;   // a lag worth reporting
constexpr double kMaxLagS = 0.1;    // a lag beyond this is forgiven
constexpr double kMaxSleepS = 0.002;
constexpr uint64_t kPinsMask = kNumPins == 64 ? ~uint64_t{0} : (uint64_t{1} << kNumPins) - 1;
constexpr uint64_t kBenchPadClocks = 4096;  // the bench host toggles its two pads this often

volatile sig_atomic_t g_signal = 0;
void on_signal(int sig) { g_signal = sig; }

double wall() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string errno_text() { return std::strerror(errno); }

// The host's bytes as the core's parser frames them (§2), for the transcript only.
class HostFramer {
  public:
    explicit HostFramer(bool quiet) : quiet_(quiet) {}
    void byte(uint8_t b, double t) {
        timeout(t);
        last_ = t;
        cur_.push_back(b);
        if (cur_.size() == 2 && cur_[1] > bsd::MAX_N) {
            char w[48];
            std::snprintf(w, sizeof w, "> %02X N=%d", cur_[0], cur_[1]);
            say(t, w, "N > 8: framing error, both bytes dropped");
            cur_.clear();
        } else if (cur_.size() >= 2 && cur_.size() == 2u + cur_[1]) {
            const Line l = host_packet(cur_);
            say(t, l.what, l.meaning);
            cur_.clear();
        }
    }
    // A partial packet left alone for RX_TIMEOUT_US is dropped by the core.
    void timeout(double t) {
        if (!cur_.empty() && t - last_ > kRxTimeoutS) {
            say(last_ + kRxTimeoutS, "> " + hex_packet(cur_, false), "incomplete: dropped after 25.6 ms");
            cur_.clear();
        }
    }
    void clear() { cur_.clear(); }

  private:
    void say(double t, const std::string& what, const std::string& meaning) {
        if (!quiet_) print_line(t, what, meaning);
    }
    bool quiet_;
    std::vector<uint8_t> cur_;
    double last_ = 0;
};

// The board: the model, its serial line at BAUD in both directions, the pads.
class Board {
  public:
    Board(VerilatedContext* ctx, const char* wave, bool quiet)
        : top_(new Vbrainstem_dio_uart{ctx}), r_(*top_->rootp), quiet_(quiet), host_(quiet) {
#if VM_TRACE
        if (wave) {
            ctx->traceEverOn(true);
            trace_.reset(new Trace);
            top_->trace(trace_.get(), 99);
            trace_->open(wave);
        }
#else
        (void)ctx;
        (void)wave;  // main() refuses --wave in a build without tracing
#endif
        r_.rx = 1;
        r_.pin_i = ext_ & kPinsMask;
        r_.clk = 0;
        top_->eval();  // the public one first: initial blocks (sim/fast_eval.h)
        sync_inputs();
        // Power-up: the outputs' values before the first reset are no pad changes.
        quiet_ = true;
        reset();
        quiet_ = quiet;
        pin_o_ = r_.pin_o;
        pin_oe_ = r_.pin_oe;
        update_pads();
        log("reset", "power-up");
    }
    ~Board() {
        if (trace_) trace_->close();
        top_->final();
    }

    uint64_t cycles() const { return cycle_; }
    double now() const { return static_cast<double>(cycle_) / kClkHz; }

    void log(const std::string& what, const std::string& meaning) {
        if (!quiet_) print_line(now(), what, meaning);
    }

    void reset() {
        // A host byte on the line is cut off; the core's output restarts with power-up.
        due_ = 0;
        rx_bit_ = -1;
        clear_frames();
        r_.rx = 1;
        rx_next_ = rxq_.empty() ? kNever : cycle_ + 1;
        tx_bit_ = -1;
        cur_.clear();
        host_.clear();
        r_.rst = 1;
        settle(*top_);
        sync_inputs();
        for (int i = 0; i < 4; ++i) clock();
        r_.rst = 0;
        settle(*top_);
        sync_inputs();
        tx_bit_ = -1;
        cur_.clear();
        clear_frames();
        due_ = 0;
        log("reset", "");
    }

    // Host -> core: queued for the rx line.
    void host_send(const uint8_t* b, size_t n) {
        rxq_.insert(rxq_.end(), b, b + n);
        if (rx_bit_ < 0 && rx_next_ == kNever) rx_next_ = cycle_;
        due_ = 0;
    }
    bool line_busy() const { return rx_bit_ >= 0 || !rxq_.empty(); }

    // Core -> host: what to write to the pty. Bytes decoded while no host has the port are lost.
    void set_host(bool open) { host_open_ = open; }
    std::vector<uint8_t>& to_host() { return out_; }

    void noise(const std::vector<uint8_t>& bytes) {
        noise_.insert(noise_.end(), bytes.begin(), bytes.end());
        due_ = 0;
    }

    // Line noise: the probability of each bit's inversion, and the counts.
    void set_ber(double p) {
        ber_ = p;
        ber_all_ = p >= 1.0;
        // A 64-bit draw below this flips the bit: P to within 2^-64.
        ber_below_ = p >= 1.0 ? UINT64_MAX : static_cast<uint64_t>(std::ldexp(p, 64));
    }
    double ber() const { return ber_; }
    void seed(uint64_t s) {
        std::seed_seq rx{uint32_t(s), uint32_t(s >> 32), 1u}, tx{uint32_t(s), uint32_t(s >> 32), 2u};
        rxn_.rng.seed(rx);
        txn_.rng.seed(tx);
    }
    std::string stats() const {
        char b[160];
        std::snprintf(b, sizeof b, "rx %" PRIu64 " of %" PRIu64 " bits flipped, tx %" PRIu64 " of %" PRIu64 " bits flipped",
                      rxn_.flips, rxn_.bits, txn_.flips, txn_.bits);
        return b;
    }

    void set_ext(int pin, int level) {
        last_event_ = cycle_;
        due_ = 0;
        if (level) ext_ |= uint64_t{1} << pin;
        else ext_ &= ~(uint64_t{1} << pin);
        update_pads();
    }
    int ext(int pin) const { return (ext_ >> pin) & 1; }

    void run_to(uint64_t end) {
        while (cycle_ < end) clock();
    }
    void idle_checks() { host_.timeout(now()); }

    // The bench's host: one command at a time, each sent when the previous reply is in,
    // heartbeats answered, two pads toggling.
    void bench_host(bool on) {
        bench_ = on;
        due_ = 0;
    }

  private:
    // Most clocks at 12 MHz have nothing for the harness: no bit due on either line, no
    // output it acts on (a pad, a strobe, link_up, a start bit on tx), no input to change
    // (they change only in busy_clock() and in the calls that set due_ to 0). Those clocks
    // are only the model's edge, with its input logic skipped (sim/fast_eval.h).
    void clock() {
        const uint64_t watch = (uint64_t{r_.pin_o} ^ pin_o_) | (uint64_t{r_.pin_oe} ^ pin_oe_) | r_.raw_trans |
                               r_.rflx_valid | (r_.link_up ^ link_up_) | ((tx_trig_ >> r_.tx) & 1u);
#if VM_TRACE
        if (trace_) return busy_clock();
#endif
        if (cycle_ < due_ && !watch) {
            posedge(r_, false);
            ++cycle_;
            return;
        }
        busy_clock();
    }

    // A clock as the lines, pads and strobes need it; then when the next one is due.
    void busy_clock() {
        if (cycle_ >= rx_next_) rx_step();
        const bool dump = trace_ && cycle_ - last_event_ < window_;
        if (dump) {  // the waveform's falling edge; the model has no logic on it
            r_.clk = 0;
            settle(*top_);
            trace_->dump(2 * cycle_);
        }
        // Outputs are sampled before the rising edge: those of the last one (sim/fast_eval.h).
        const int tx = r_.tx;
        // The core's frame: bit k spans kDiv clocks from the start bit's first clock; each bit
        // is drawn for noise as it begins (a next start bit may begin as the stop bit ends).
        if (txf_bit_ >= 0 && cycle_ == txf_next_) {
            if (++txf_bit_ == 10) {
                txf_bit_ = -1;
                txf_flip_ = 0;
            } else {
                txf_flip_ = flip(txn_, txf_bit_);
                txf_next_ += kDiv;
            }
        }
        if (tx_bit_ < 0) {
            if (!tx) {
                tx_bit_ = 0;
                tx_sample_ = cycle_ + kDiv / 2;
                last_event_ = cycle_;
                txf_bit_ = 0;
                txf_next_ = cycle_ + kDiv;
                txf_flip_ = flip(txn_, 0);
            }
        } else if (cycle_ == tx_sample_) {
            tx_step(tx);
        }
        // The host's UART, on the line as the noise left it.
        const int line = tx ^ txf_flip_;
        if (hx_bit_ < 0) {
            if (!line) {
                hx_bit_ = 0;
                hx_sample_ = cycle_ + kDiv / 2;
            }
        } else if (cycle_ == hx_sample_) {
            host_uart_step(line);
        }
        if (r_.pin_o != pin_o_ || r_.pin_oe != pin_oe_) pads_changed();
        if (r_.raw_trans) raw_inputs(r_.raw_trans);
        if (r_.rflx_valid) {
            last_event_ = cycle_;
            const Line l = rflx(r_.rflx_id, r_.rflx_data);
            log(l.what, l.meaning);
        }
        if (r_.link_up != link_up_) {
            link_up_ = r_.link_up;
            log(std::string("* link_up ") + (link_up_ ? "1" : "0"),
                link_up_ ? "the host answers the heartbeat" : "a heartbeat went unanswered");
        }
        if (!noise_.empty() && tx_bit_ < 0 && cur_.empty()) send_noise();
        if (bench_ && cycle_ % kBenchPadClocks == 0) r_.pin_i ^= 0x18 & kPinsMask;
        if (dump) {  // through the public eval(): it marks the activity the waveform records
            r_.clk = 1;
            top_->eval();
            sync_inputs();
            trace_->dump(2 * cycle_ + 1);
        } else {
            posedge(r_, inputs_.changed(r_.rst, r_.rx, r_.pin_i));
        }
        ++cycle_;
        // The earliest clock with a line's bit or the bench's pads due (no later than any of
        // busy_clock()'s time tests), and the tx levels that need one: a start bit while the
        // transcript's or the host's decoder waits for one (the host's sees the noise).
        uint64_t due = noise_.empty() ? rx_next_ : 0;
        if (txf_bit_ >= 0 && txf_next_ < due) due = txf_next_;
        if (tx_bit_ >= 0 && tx_sample_ < due) due = tx_sample_;
        if (hx_bit_ >= 0 && hx_sample_ < due) due = hx_sample_;
        if (bench_) {
            const uint64_t pads = (cycle_ + kBenchPadClocks - 1) / kBenchPadClocks * kBenchPadClocks;
            if (pads < due) due = pads;
        }
        due_ = due;
        tx_trig_ = (tx_bit_ < 0 ? 1u : 0u) | (hx_bit_ < 0 ? 1u << txf_flip_ : 0u);
    }

    // After a public eval(): the inputs its input logic ran with (sim/fast_eval.h).
    void sync_inputs() { inputs_.sync(r_.rst, r_.rx, r_.pin_i); }

    // The rx line: start bit, 8 data bits LSB first, stop bit, each kDiv clocks.
    void rx_step() {
        last_event_ = cycle_;
        if (rx_bit_ >= 0) {
            ++rx_bit_;
            if (rx_bit_ < 10) {
                const int level = rx_bit_ <= 8 ? (rx_byte_ >> (rx_bit_ - 1)) & 1 : 1;
                r_.rx = level ^ flip(rxn_, rx_bit_);
                rx_next_ = cycle_ + kDiv;
                return;
            }
            rx_bit_ = -1;  // the stop bit is over: the byte has crossed the line
            host_.byte(rx_byte_, now());
            log_flips("rx", rx_byte_, rxn_);
        }
        if (rxq_.empty()) {
            rx_next_ = kNever;
            return;
        }
        rx_byte_ = rxq_.front();
        rxq_.pop_front();
        rx_bit_ = 0;
        r_.rx = 0 ^ flip(rxn_, 0);
        rx_next_ = cycle_ + kDiv;
    }

    // Frames cut off by a reset: their flips are not reported, the host's UART starts afresh.
    void clear_frames() {
        for (Noise* n : {&rxn_, &txn_}) {
            n->mask = 0;
            n->where.clear();
        }
        txf_bit_ = -1;
        txf_flip_ = 0;
        hx_bit_ = -1;
    }

    // Per line: its generator, and the bits of the frame on it now that were flipped.
    struct Noise {
        std::mt19937_64 rng;
        uint64_t bits = 0, flips = 0;
        unsigned mask = 0;               // bit k of the frame (0 start, 1-8 data, 9 stop)
        std::vector<uint64_t> where;     // their positions on the line
    };

    // Bit k of a frame begins on line n: inverted?
    int flip(Noise& n, int k) {
        const uint64_t at = n.bits++;
        if (ber_ == 0) return 0;
        if (!ber_all_ && n.rng() >= ber_below_) return 0;
        ++n.flips;
        n.mask |= 1u << k;
        n.where.push_back(at);
        return 1;
    }

    void log_flips(const char* dir, uint8_t byte, Noise& n) {
        if (!n.mask) return;
        std::string bits, where;
        for (int k = 0; k < 10; ++k) {
            if (!(n.mask & (1u << k))) continue;
            bits += k == 0 ? " start" : k == 9 ? " stop" : " d" + std::to_string(k - 1);
        }
        for (uint64_t w : n.where) where += (where.empty() ? "" : " ") + std::to_string(w);
        char what[32];
        std::snprintf(what, sizeof what, "* noise %s %02X", dir, byte);
        log(what, "flipped" + bits + " [bits " + where + "]");
        n.mask = 0;
        n.where.clear();
    }

    // The host's UART on the noisy tx line; its bytes go to the pty.
    void host_uart_step(int level) {
        if (hx_bit_ == 0) {
            if (level) {  // not a start bit after all
                hx_bit_ = -1;
                return;
            }
        } else if (hx_bit_ <= 8) {
            hx_shift_ = static_cast<uint8_t>((hx_shift_ >> 1) | (level ? 0x80 : 0));
        } else {
            hx_bit_ = -1;
            if (host_open_) out_.push_back(hx_shift_);  // a 0 stop bit too (no INPCK)
            return;
        }
        ++hx_bit_;
        hx_sample_ += kDiv;
    }

    // The tx line, sampled in the middle of each bit.
    void tx_step(int tx) {
        last_event_ = cycle_;
        if (tx_bit_ == 0) {
            if (tx) {  // not a start bit after all
                tx_bit_ = -1;
                return;
            }
        } else if (tx_bit_ <= 8) {
            tx_shift_ = static_cast<uint8_t>((tx_shift_ >> 1) | (tx ? 0x80 : 0));
        } else {
            tx_bit_ = -1;
            if (tx) core_byte(tx_shift_);
            else log("* tx framing error", "");
            log_flips("tx", tx_shift_, txn_);
            return;
        }
        ++tx_bit_;
        tx_sample_ += kDiv;
    }

    void core_byte(uint8_t b) {
        if (!host_open_) lost_ = true;
        cur_.push_back(b);
        if (cur_.size() >= 2 && cur_.size() == 2u + cur_[1]) {
            std::vector<uint8_t> p;
            p.swap(cur_);
            if (bench_) bench_reply(p);
            Line l = core_packet(p);
            if (lost_) l.meaning += (l.meaning.empty() ? "" : "  ") + std::string("[lost: no host]");
            log(l.what, l.meaning);
            lost_ = false;
        }
    }

    void send_noise() {
        std::vector<uint8_t> b;
        b.swap(noise_);
        if (host_open_) out_.insert(out_.end(), b.begin(), b.end());
        log("< noise " + hex_bytes(b), host_open_ ? "between packets" : "[lost: no host]");
    }

    void pads_changed() {
        last_event_ = cycle_;
        const uint64_t o = r_.pin_o, oe = r_.pin_oe;
        for (int p = 0; p < kNumPins; ++p) {
            const uint64_t m = uint64_t{1} << p;
            const bool was = pin_oe_ & m, is = oe & m;
            if (is && (!was || ((o ^ pin_o_) & m)))
                log("pin " + std::to_string(p) + ((o & m) ? " driven high" : " driven low"), "");
            else if (was && !is)
                log("pin " + std::to_string(p) + " released", "input: " + std::to_string(ext(p)));
        }
        pin_o_ = o;
        pin_oe_ = oe;
        update_pads();
    }

    void update_pads() { r_.pin_i = ((pin_oe_ & pin_o_) | (~pin_oe_ & ext_)) & kPinsMask; }

    void raw_inputs(uint64_t bits) {
        last_event_ = cycle_;
        for (int p = 0; p < kNumPins; ++p) {
            if (bits & (uint64_t{1} << p)) {
                const Line l = raw_input(p);
                log(l.what, l.meaning);
            }
        }
    }

    void bench_reply(const std::vector<uint8_t>& p) {
        using namespace bsd;
        constexpr uint8_t A = kModuleAddr, H = DEVCODE_HOST;
        struct Cmd {
            bool reply;
            std::vector<uint8_t> bytes;
        };
        static const std::vector<Cmd> cmds = {
            {false, {A, 3, CMD_DIG_CFG, 3, 0x19}}, {true, {A, 2, CMD_DIG_IO, H | 0}},
            {true, {A, 2, CMD_DIG_CFG, 4}},        {true, {A, 2, CMD_PTIME_RD, H | 3}},
            {false, {A, 2, CMD_DIG_RST, 2}},       {true, {A, 2, CMD_DIG_IO, H | 2}}};
        if (p.size() == 4 && p[2] == CMD_HB) {
            const uint8_t answer[] = {A, 2, CMD_HB, static_cast<uint8_t>(p[3] + HB_ANSWER_OFFSET)};
            host_send(answer, sizeof answer);
            return;
        }
        // Commands without a reply go along with the next one.
        for (;;) {
            const Cmd& c = cmds[bench_k_++ % cmds.size()];
            host_send(c.bytes.data(), c.bytes.size());
            if (c.reply) break;
        }
    }

    std::unique_ptr<Vbrainstem_dio_uart> top_;
    // The ports are read and written on the model's root, where they live: the top's members
    // are references to them, one load more each.
    Vbrainstem_dio_uart___024root& r_;
    std::unique_ptr<Trace> trace_;
    // Every input but clk, as sync_inputs() and clock() pass them.
    Inputs<CData, CData, std::remove_reference_t<decltype(Vbrainstem_dio_uart::pin_i)>> inputs_;
    bool quiet_;
    HostFramer host_;
    uint64_t cycle_ = 0;
    uint64_t last_event_ = 0;
    uint64_t due_ = 0;         // clock() runs busy_clock() from this cycle on
    unsigned tx_trig_ = 3;     // bit v: tx at level v needs busy_clock()
    // Without a port event (a bit on either line, a pad, a strobe) for this long, the
    // waveform pauses: an idle hour would otherwise fill the disk.
    const uint64_t window_ = static_cast<uint64_t>((200e-6 > 20.0 / kBaud ? 200e-6 : 20.0 / kBaud) * kClkHz);
    // rx line
    std::deque<uint8_t> rxq_;
    int rx_bit_ = -1;
    uint64_t rx_next_ = kNever;
    uint8_t rx_byte_ = 0;
    // tx line
    int tx_bit_ = -1;
    uint64_t tx_sample_ = 0;
    uint8_t tx_shift_ = 0;
    std::vector<uint8_t> cur_;  // the core's packet so far
    bool lost_ = false;
    // the core's frame on the tx line, for the noise; the host's UART after it
    int txf_bit_ = -1;
    uint64_t txf_next_ = 0;
    int txf_flip_ = 0;
    int hx_bit_ = -1;
    uint64_t hx_sample_ = 0;
    uint8_t hx_shift_ = 0;
    // line noise
    double ber_ = 0;
    bool ber_all_ = false;
    uint64_t ber_below_ = 0;
    Noise rxn_, txn_;
    bool host_open_ = false;
    std::vector<uint8_t> out_;
    std::vector<uint8_t> noise_;
    // pads
    uint64_t ext_ = ~uint64_t{0};
    uint64_t pin_o_ = 0, pin_oe_ = 0;
    bool link_up_ = false;
    bool bench_ = false;
    size_t bench_k_ = 0;
};

// The pty and the symlink to it.
class Port {
  public:
    Port() {
        master_ = posix_openpt(O_RDWR | O_NOCTTY);
        if (master_ < 0) throw Fail{"cannot open a pseudo-terminal (posix_openpt): " + errno_text()};
        if (grantpt(master_) || unlockpt(master_)) throw Fail{"cannot unlock the pseudo-terminal: " + errno_text()};
        const char* name = ptsname(master_);
        if (!name) throw Fail{"cannot name the pseudo-terminal (ptsname): " + errno_text()};
        slave_ = name;
        // Raw, once: the setting stays with the pty while the master is open.
        const int s = ::open(slave_.c_str(), O_RDWR | O_NOCTTY);
        if (s < 0) throw Fail{"cannot open the pseudo-terminal " + slave_ + ": " + errno_text()};
        termios t{};
        if (tcgetattr(s, &t) == 0) {
            cfmakeraw(&t);
            t.c_cc[VMIN] = 1;
            t.c_cc[VTIME] = 0;
            tcsetattr(s, TCSANOW, &t);
        }
        ::close(s);
        fcntl(master_, F_SETFL, fcntl(master_, F_GETFL) | O_NONBLOCK);
        fcntl(master_, F_SETFD, FD_CLOEXEC);
    }
    ~Port() {
        unlink_link();
        if (lock_ >= 0) ::close(lock_);
        if (master_ >= 0) ::close(master_);
    }

    const std::string& slave() const { return slave_; }
    int master() const { return master_; }
    bool host() const { return host_; }

    void link(const std::string& path) {
        const std::string lock = path + ".lock";
        lock_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (lock_ < 0) throw Fail{"cannot create " + lock + ": " + errno_text()};
        if (flock(lock_, LOCK_EX | LOCK_NB))
            throw Fail{"another virtual module is running with the link " + path + " (it holds " + lock + ")"};
        const std::string tmp = path + ".tmp" + std::to_string(getpid());
        ::unlink(tmp.c_str());
        if (symlink(slave_.c_str(), tmp.c_str()) || rename(tmp.c_str(), path.c_str()))
            throw Fail{"cannot make the link " + path + ": " + errno_text()};
        link_ = path;
    }

    void unlink_link() {
        if (link_.empty()) return;
        char target[PATH_MAX];
        const ssize_t n = readlink(link_.c_str(), target, sizeof target - 1);
        if (n >= 0 && std::string(target, n) == slave_) ::unlink(link_.c_str());
        link_.clear();
    }

    // Reads what the host wrote (appended to `in`); returns -1 when the host just closed
    // the port, 1 when it just opened it, else 0.
    int read(std::vector<uint8_t>& in) {
        uint8_t buf[4096];
        bool present = host_;
        for (;;) {
            const ssize_t n = ::read(master_, buf, sizeof buf);
            if (n > 0) {
                in.insert(in.end(), buf, buf + n);
                present = true;
                continue;
            }
            if (n < 0 && errno == EINTR) continue;
            present = n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK);
            break;
        }
        if (present == host_) return 0;
        host_ = present;
        // What the closing host had not read is gone, as on a serial port.
        if (!present) tcflush(master_, TCOFLUSH);
        return present ? 1 : -1;
    }

    // Writes to the host; returns how many bytes did not fit (a host that does not read).
    size_t write(const std::vector<uint8_t>& out) {
        size_t done = 0;
        while (done < out.size()) {
            const ssize_t n = ::write(master_, out.data() + done, out.size() - done);
            if (n > 0) done += n;
            else if (n < 0 && errno == EINTR) continue;
            else break;
        }
        return out.size() - done;
    }

  private:
    int master_ = -1;
    int lock_ = -1;
    bool host_ = false;
    std::string slave_;
    std::string link_;
};

// Standard input, a line at a time, without blocking and without changing the file's flags
// (stdin may be the shell's terminal).
class Console {
  public:
    bool eof() const { return eof_; }
    // Parses every complete line that has arrived; throws Fail with "stdin:N: ".
    void read(std::deque<Step>& steps) {
        if (eof_) return;
        pollfd p{0, POLLIN, 0};
        if (::poll(&p, 1, 0) <= 0) return;
        if (p.revents & POLLNVAL) {  // no standard input at all
            eof_ = true;
            return;
        }
        if (!(p.revents & (POLLIN | POLLHUP | POLLERR))) return;
        char buf[4096];
        const ssize_t n = ::read(0, buf, sizeof buf);
        if (n < 0) {
            if (errno == EINTR || errno == EAGAIN) return;
            eof_ = true;
        } else if (n == 0) {
            eof_ = true;
        } else {
            text_.append(buf, n);
        }
        for (size_t nl; (nl = text_.find('\n')) != std::string::npos;) {
            line(text_.substr(0, nl), steps);
            text_.erase(0, nl + 1);
        }
        if (eof_ && !text_.empty()) {
            line(text_, steps);
            text_.clear();
        }
    }

  private:
    void line(const std::string& text, std::deque<Step>& steps) {
        ++line_;
        Step st;
        try {
            if (parse_line(text, line_, kNumPins, Dialect::Stdin, st)) steps.push_back(st);
        } catch (const Fail& f) {
            const std::string msg = "stdin:" + std::to_string(line_) + ": " + f.msg;
            std::istringstream words(text);
            std::string first;
            words >> first;
            if (first != "ber") throw Fail{msg};
            std::fflush(stdout);
            std::fprintf(stderr, "error: %s; the rate stays as it was\n", msg.c_str());
        }
    }
    bool eof_ = false;
    int line_ = 0;
    std::string text_;
};

struct Pulse {
    int pin = -1;
    int level = 0;
    uint64_t end = kNever;
};

const char* signal_name(int sig) {
    switch (sig) {
        case SIGINT: return "SIGINT";
        case SIGTERM: return "SIGTERM";
        case SIGHUP: return "SIGHUP";
        default: return "a signal";
    }
}

// The interactive run; returns the reason it ended.
std::string run(Board& b, Port& port) {
    Console console;
    std::deque<Step> steps;
    uint64_t busy_until = 0;  // the stdin line after a wait or pulse runs from here
    Pulse pulse;
    std::vector<uint8_t> in;
    double origin = wall() - b.now();  // wall time of simulated time 0
    double window_wall = wall();
    double last_turn = window_wall, stall = 0;  // the longest time between two turns of this loop
    uint64_t window_cycles = b.cycles();
    double lost_report = 0;
    size_t lost = 0;
    for (;;) {
        if (g_signal) return signal_name(g_signal);
        // Standard input first: a line typed after the host opened (or closed) the port then
        // runs with the port's new state, read just below.
        console.read(steps);
        // The port: the host's bytes onto the rx line, the core's bytes to the host.
        in.clear();
        const int change = port.read(in);
        if (change > 0) b.log("host opened the port", "");
        if (change < 0) {
            b.log("host closed the port", "");
            b.to_host().clear();
        }
        b.set_host(port.host());
        if (!in.empty()) b.host_send(in.data(), in.size());
        if (port.host() && !b.to_host().empty()) {
            lost += port.write(b.to_host());
            b.to_host().clear();
        }
        // The transcript of the chunk just run goes out only now: a host that has read a
        // packet's line may count on its bytes being in the pty.
        std::fflush(stdout);
        if (lost && wall() - lost_report >= 1.0) {
            std::fprintf(stderr, "the host is not reading: %zu bytes to it lost\n", lost);
            lost = 0;
            lost_report = wall();
        }
        // The stdin lines, in order.
        if (b.cycles() >= pulse.end) {
            b.set_ext(pulse.pin, pulse.level);
            pulse = Pulse{};
        }
        while (!steps.empty() && b.cycles() >= busy_until && pulse.end == kNever) {
            const Step st = steps.front();
            steps.pop_front();
            const uint64_t dur = static_cast<uint64_t>(st.seconds * kClkHz + 0.5);
            switch (st.op) {
                case Op::PinSet:
                    b.set_ext(st.pin, st.level);
                    b.log("pin " + std::to_string(st.pin) + (st.level ? " high" : " low"), "");
                    break;
                case Op::PinPulse: {
                    const int before = b.ext(st.pin);
                    b.set_ext(st.pin, !before);
                    char w[64];
                    std::snprintf(w, sizeof w, "pin %d pulse %s %.1f us", st.pin, before ? "low" : "high",
                                  st.seconds * 1e6);
                    b.log(w, "");
                    pulse = Pulse{st.pin, before, b.cycles() + dur};
                    busy_until = pulse.end;
                    break;
                }
                case Op::Wait: busy_until = b.cycles() + dur; break;
                case Op::Reset: b.reset(); break;
                case Op::Noise: b.noise(st.bytes); break;
                case Op::Ber: {
                    b.set_ber(st.ber);
                    char w[48];
                    std::snprintf(w, sizeof w, "ber %g", st.ber);
                    b.log(w, st.ber > 0 ? "line noise on both lines" : "line noise off");
                    break;
                }
                case Op::Stats:
                    std::printf("stats: ber %g: %s\n", b.ber(), b.stats().c_str());
                    break;
                case Op::Quit: return "quit";
                case Op::Send:
                case Op::Expect: break;  // not stdin lines (the parser refuses them)
            }
        }
        if (console.eof() && steps.empty() && b.cycles() >= busy_until && pulse.end == kNever)
            return "end of input";
        b.idle_checks();
        // Pacing: never past the wall clock.
        // Once a second: behind by more than kBehindS now, and slower than real time over
        // that second? Or did this loop not run for more than kBehindS (the machine is busy)?
        // A stall that has been made up since is still worth a line: a host may have seen the
        // bytes of a packet stop for that long (the host library drops a partial packet after
        // 0.1 s without a byte).
        const double t = wall();
        if (t - last_turn > stall) stall = t - last_turn;
        last_turn = t;
        double lag = (t - origin) - b.now();
        if (t - window_wall >= 1.0) {
            const double ratio = (b.cycles() - window_cycles) / double(kClkHz) / (t - window_wall);
            if ((lag > kBehindS && ratio < 1.0) || stall > kBehindS) {
                if (stall > kBehindS) std::fprintf(stderr, "behind real time: x%.2f, stalled %.3f s\n", ratio, stall);
                else std::fprintf(stderr, "behind real time: x%.2f\n", ratio);
            }
            window_wall = t;
            window_cycles = b.cycles();
            stall = 0;
        }
        if (lag > kMaxLagS) {
            origin += lag - kMaxLagS;
            lag = kMaxLagS;
        }
        // The next chunk: 1 ms, or up to the end of a wait or pulse; run it once it is due.
        const uint64_t allowed = static_cast<uint64_t>((t - origin) * kClkHz);
        uint64_t target = b.cycles() + kChunk;
        if (busy_until > b.cycles() && busy_until < target) target = busy_until;
        if (allowed >= target) {
            b.run_to(target);
            continue;
        }
        // Ahead: sleep until it is due, or the host or stdin has something.
        double sleep = (target - allowed) / double(kClkHz);
        if (sleep > kMaxSleepS) sleep = kMaxSleepS;
        pollfd fds[2] = {{0, POLLIN, 0}, {port.master(), POLLIN, 0}};
        // While no host has the port, the master reports POLLHUP at once: leave it out.
        const nfds_t nfds = console.eof() ? 0 : 1;
        pollfd* first = console.eof() ? &fds[1] : &fds[0];
        const nfds_t count = nfds + (port.host() ? 1 : 0);
        timespec ts{0, static_cast<long>(sleep * 1e9)};
        std::fflush(stdout);  // the lines of this turn's stdin steps
        if (count) ppoll(first, count, &ts, nullptr);
        else nanosleep(&ts, nullptr);
    }
}

double cpu() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

// Unpaced, for `seconds` of wall time; the ratio to real time per wall second (what a host
// sees on this machine now) and per CPU second (what a core of its own would give).
void bench(Board& b, double seconds) {
    b.bench_host(true);
    const uint8_t start[] = {static_cast<uint8_t>(kModuleAddr), 2, bsd::CMD_DIG_CFG, 0};
    b.host_send(start, sizeof start);
    b.run_to(b.cycles() + kClkHz / 20);  // warm up: 50 ms
    const uint64_t c0 = b.cycles();
    const double t0 = wall(), p0 = cpu();
    double t = t0;
    while (t - t0 < seconds) {
        b.run_to(b.cycles() + kChunk);
        t = wall();
    }
    const double sim = (b.cycles() - c0) / double(kClkHz), p = cpu() - p0;
    std::printf("bench: clk %" PRIu64 " Hz, baud %" PRIu64 ": simulated %.6f s in %.3f s wall, %.3f s cpu: "
                "ratio %.3f wall, %.3f cpu; %.0f cycles per cpu second\n",
                kClkHz, kBaud, sim, t - t0, p, sim / (t - t0), sim / p, (b.cycles() - c0) / p);
}

const char* kUsage =
    "usage: virtual [--link PATH] [--wave FILE] [--ber P] [--seed N]\n"
    "       virtual --bench SECONDS\n"
    "  Runs brainstem_dio_uart behind a pseudo-terminal and prints 'port: /dev/pts/N'.\n"
    "  --link PATH      keep a symlink PATH -> the pty while running\n"
    "  --wave FILE      record a waveform (paused while the lines and pads are idle);\n"
    "                   only in the build with tracing (make virtual WAVES=1)\n"
    "  --ber P          line noise: flip each bit on both serial lines with probability P (0..1)\n"
    "  --seed N         the noise generators' seed (0..2^64-1; default: a random one, printed)\n"
    "  --bench SECONDS  no pty: run unpaced for SECONDS of wall time with a busy host,\n"
    "                   print the ratio of simulated to real time\n"
    "  Standard input: pin N high|low, pin N pulse TIME, wait TIME, reset, noise BYTES,\n"
    "  ber P, stats, quit.\n"
    "  The host's baud setting on the pty is ignored: the line runs at the build's BAUD.\n";

}  // namespace

int main(int argc, char** argv) {
    std::string link, wave;
    double bench_seconds = 0, ber = 0;
    uint64_t seed = 0;
    bool have_seed = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has_value = i + 1 < argc;
        if (a == "--link" && has_value) link = argv[++i];
        else if (a == "--wave" && has_value) wave = argv[++i];
        else if (a == "--ber" && has_value) {
            if (!parse_ber(argv[++i], ber)) {
                std::fprintf(stderr, "error: --ber needs %s, not '%s'\n%s", kBerHelp, argv[i], kUsage);
                return 2;
            }
        } else if (a == "--seed" && has_value) {
            const char* v = argv[++i];
            char* end = nullptr;
            errno = 0;
            seed = std::strtoull(v, &end, 10);
            if (errno || !end || *end || !std::isdigit((unsigned char)v[0])) {
                std::fprintf(stderr, "error: --seed needs a decimal number from 0 to 2^64-1, not '%s'\n%s", v, kUsage);
                return 2;
            }
            have_seed = true;
        }
        else if (a == "--bench" && has_value) {
            char* end = nullptr;
            bench_seconds = std::strtod(argv[++i], &end);
            if (!end || *end || !(bench_seconds > 0)) {
                std::fprintf(stderr, "error: --bench needs a number of seconds, not '%s'\n%s", argv[i], kUsage);
                return 2;
            }
        } else if (a == "--help" || a == "-h") {
            std::fputs(kUsage, stdout);
            return 0;
        } else if (!a.empty() && a[0] == '+') {
            continue;  // Verilator plusargs
        } else {
            const bool takes_value = a == "--link" || a == "--wave" || a == "--bench" || a == "--ber" || a == "--seed";
            const std::string why = takes_value          ? "option '" + a + "' needs a value"
                                    : a.size() > 1 && a[0] == '-' ? "unknown option '" + a + "'"
                                                                 : "unexpected argument '" + a + "'";
            std::fprintf(stderr, "error: %s\n%s", why.c_str(), kUsage);
            return 2;
        }
    }
#if !VM_TRACE
    // Tracing costs every clock, so only make's WAVES=1 build has it (the Makefile).
    if (!wave.empty()) {
        std::fprintf(stderr, "error: --wave needs the build with tracing: make virtual WAVES=1 (or virtual-build WAVES=1)\n%s",
                     kUsage);
        return 2;
    }
#endif
    // Fully buffered: run() flushes a chunk's transcript after writing its bytes to the pty.
    std::setvbuf(stdout, nullptr, _IOFBF, 1 << 16);
    auto ctx = std::make_unique<VerilatedContext>();
    ctx->commandArgs(argc, argv);
    if (bench_seconds > 0) {
        Board b(ctx.get(), nullptr, true);
        bench(b, bench_seconds);
        return 0;
    }
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;  // no SA_RESTART: a signal ends the sleep at once
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    sigaction(SIGHUP, &sa, nullptr);
    signal(SIGPIPE, SIG_IGN);
    std::unique_ptr<Port> port;
    std::unique_ptr<Board> b;
    int status = 0;
    try {
        port.reset(new Port);
        if (!link.empty()) port->link(link);
        char hb[32] = "off";
        if (kHbRate) std::snprintf(hb, sizeof hb, "every %.1f ms", kHbRate * 25.6);
        std::printf("brainstem_dio virtual module: clk %.3f MHz, %" PRIu64 " baud, heartbeat %s, module %d, %d pins\n",
                    kClkHz / 1e6, kBaud, hb, kModuleAddr, kNumPins);
        std::printf("port: %s\n", port->slave().c_str());
        if (!link.empty()) std::printf("link: %s\n", link.c_str());
        if (!have_seed) seed = (uint64_t(std::random_device{}()) << 32) ^ std::random_device{}() ^ uint64_t(wall() * 1e9);
        std::printf("line noise: ber %g, seed %" PRIu64 " (--seed %" PRIu64 " repeats it)\n", ber, seed, seed);
        std::fflush(stdout);
        b.reset(new Board(ctx.get(), wave.empty() ? nullptr : wave.c_str(), false));
        b->seed(seed);
        b->set_ber(ber);
        const std::string why = run(*b, *port);
        std::printf("stats: ber %g: %s\n", b->ber(), b->stats().c_str());
        std::printf("done (%s): %.6f s simulated, %" PRIu64 " cycles%s%s\n", why.c_str(), b->now(), b->cycles(),
                    wave.empty() ? "" : ", waveform ", wave.c_str());
    } catch (const Fail& f) {
        std::fflush(stdout);
        std::fprintf(stderr, "error: %s\n", f.msg.c_str());
        status = 1;
    }
    b.reset();
    port.reset();  // removes the link
    return status;
}
