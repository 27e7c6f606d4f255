// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Two-flop synchronizer for asynchronous pad inputs. No reset: it only
// carries levels, and after two clocks it holds the pad whatever it started as.
module bsd_sync #(
    parameter integer WIDTH = 1
) (
    input  wire             clk,
    input  wire [WIDTH-1:0] d_i,
    output wire [WIDTH-1:0] q_o
);
    reg [WIDTH-1:0] meta_q;
    reg [WIDTH-1:0] sync_q;

    always @(posedge clk) begin
        meta_q <= d_i;
        sync_q <= meta_q;
    end

    assign q_o = sync_q;

`ifdef FORMAL
`include "bsd_sync_props.vh"
`endif
endmodule
`default_nettype wire
