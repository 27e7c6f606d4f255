// SPDX-License-Identifier: Apache-2.0
`timescale 1ns / 1ps
`default_nettype none
// Self-checking long-run check of bsd_tick_gen: no drift over CLOCKS clocks
// (default CLK_HZ clocks = 1 s of clk time). tb/bsd_tick_gen/test_bsd_tick_gen_drift.py runs it
// on both simulators (the Verilator build uses --binary).
//
// Edge 0 is the rising edge at which rst is last sampled 1; edge n is the n-th
// rising edge after it. At every strobe k (k = 1, 2, ...), seen right after edge n:
//     0 <= n * RATE_HZ - k * CLK_HZ < RATE_HZ      (n = ceil(k * CLK_HZ / RATE_HZ))
// every strobe is one clock wide, tick_o is 0 in reset, and after edge CLOCKS the
// strobe count is exactly floor(CLOCKS * RATE_HZ / CLK_HZ) (= RATE_HZ for 1 s).
// Prints one line "tick_drift_tb: PASS ..." or "tick_drift_tb: FAIL ..."; a failure
// also ends with $fatal (non-zero exit code).
module tick_drift_tb;
    parameter integer CLK_HZ  = 48_000_000;
    parameter integer RATE_HZ = 625_000;
    parameter integer CLOCKS  = CLK_HZ;
    parameter integer RESET_CLOCKS = 4;
    // The DUT's own CLK_HZ: differs from CLK_HZ only in the negative control that
    // shows the checker catches a drifting generator.
    parameter integer DUT_CLK_HZ = CLK_HZ;

    localparam [63:0] CLK64    = {32'd0, CLK_HZ};
    localparam [63:0] RATE64   = {32'd0, RATE_HZ};
    localparam [63:0] CLOCKS64 = {32'd0, CLOCKS};
    localparam [63:0] EXPECTED = CLOCKS64 * RATE64 / CLK64;

    reg  clk = 1'b0;
    reg  rst = 1'b1;
    wire tick;

    bsd_tick_gen #(
        .CLK_HZ (DUT_CLK_HZ),
        .RATE_HZ(RATE_HZ)
    ) dut (
        .clk   (clk),
        .rst   (rst),
        .tick_o(tick)
    );

    always #5 clk = ~clk;

    reg  [31:0] cyc = 32'd0;   // rising edges while in reset
    reg  [31:0] idx = 32'd0;   // index of the previous edge (0 = a reset edge)
    reg  [63:0] strobes = 64'd0;
    reg         prev_tick = 1'b0;
    reg  [63:0] lhs, rhs, lag;
    reg  [63:0] lag_min = 64'hFFFF_FFFF_FFFF_FFFF;
    reg  [63:0] lag_max = 64'd0;
    integer     errors = 0;

    task fail(input [8*64-1:0] what);
        begin
            errors = errors + 1;
            if (errors <= 10)
                $display("tick_drift_tb: error at edge %0d, strobe %0d: %0s", idx, strobes, what);
        end
    endtask

    // Everything below uses pre-edge values: `rst` is what the DUT samples at this
    // edge and `tick` is its output after the previous edge (edge `idx`).
    always @(posedge clk) begin
        if (rst) begin
            cyc <= cyc + 32'd1;
            rst <= (cyc < RESET_CLOCKS - 32'd1);
            idx <= 32'd0;
        end else begin
            idx <= idx + 32'd1;
        end

        if (tick === 1'b1) begin
            if (idx == 32'd0) fail("tick_o high in reset");
            if (prev_tick) fail("strobe wider than one clock");
            strobes = strobes + 64'd1;
            lhs = {32'd0, idx} * RATE64;
            rhs = strobes * CLK64;
            if (lhs < rhs || lhs - rhs >= RATE64) begin
                fail("phase outside [0, 1) clock of k*CLK_HZ/RATE_HZ");
            end else begin
                lag = lhs - rhs;
                if (lag < lag_min) lag_min = lag;
                if (lag > lag_max) lag_max = lag;
            end
        end else if (tick !== 1'b0 && idx != 32'd0) begin
            fail("tick_o is X/Z after reset");
        end
        prev_tick <= (tick === 1'b1);

        if (idx == CLOCKS) begin
            // tick after edge CLOCKS has just been checked above.
            if (strobes != EXPECTED) begin
                errors = errors + 1;
                $display("tick_drift_tb: %0d strobes in %0d clocks, expected %0d", strobes,
                         CLOCKS, EXPECTED);
            end
            if (errors == 0) begin
                $display("tick_drift_tb: PASS CLK_HZ=%0d RATE_HZ=%0d clocks=%0d strobes=%0d phase lag %0d..%0d /%0d clock",
                         CLK_HZ, RATE_HZ, CLOCKS, strobes, lag_min, lag_max, RATE_HZ);
                $finish;
            end else begin
                $display("tick_drift_tb: FAIL CLK_HZ=%0d RATE_HZ=%0d clocks=%0d strobes=%0d errors=%0d",
                         CLK_HZ, RATE_HZ, CLOCKS, strobes, errors);
                $fatal(1, "tick_drift_tb failed");
            end
        end
    end
endmodule
`default_nettype wire
