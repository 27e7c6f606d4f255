// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Grants the oldest requester. A request is "born" on the clock it rises;
// requesters born on the same clock rank by index (lowest first). Keeps an
// age matrix by columns: older_q[K*i +: K] has bit j set when requester j is
// older than requester i. The grant comes from registers only (the requests
// and ages of the previous clock), so a request is granted one clock after it
// rises at the earliest, and a request that has just dropped must be in
// exclude_i for that one clock.
module bsd_age_arb #(
    parameter integer K = 4
) (
    input  wire         clk,
    input  wire         rst,
    input  wire [K-1:0] req_i,
    input  wire [K-1:0] exclude_i,  // pending but not eligible (being served)
    output wire [K-1:0] gnt_o       // one-hot or zero
);
    reg  [K-1:0]   req_q;
    reg  [K*K-1:0] older_q;
    reg  [K*K-1:0] older_d;
    wire [K-1:0]   born = req_i & ~req_q;
    wire [K-1:0]   cand = req_q & ~exclude_i;
    reg  [K-1:0]   gnt;

    assign gnt_o = gnt;

    // below[i]: the requesters with a lower index than i.
    function [K-1:0] below(input integer i);
        below = ({{(K-1){1'b0}}, 1'b1} << i) - 1'b1;
    endfunction

    integer i;
    always @* begin
        for (i = 0; i < K; i = i + 1) begin
            // A newborn is younger than everything already waiting and than
            // same-clock newborns of lower index; a waiting requester stays
            // older than every newborn.
            older_d[K*i +: K] = born[i] ? (req_q | (born & below(i)))
                                        : (older_q[K*i +: K] & ~born);
            gnt[i] = cand[i] && !(|(cand & older_q[K*i +: K]));
        end
    end

    always @(posedge clk) begin
        req_q   <= req_i;
        older_q <= older_d;
        if (rst) begin
            req_q   <= {K{1'b0}};
            older_q <= {K*K{1'b0}};
        end
    end

`ifndef SYNTHESIS
`ifndef FORMAL  // Yosys takes no $fatal in an always block; the formal props assert it
    // The grant is one-hot or zero.
    always @(posedge clk) begin
        if (!rst && (gnt & (gnt - 1'b1)) != {K{1'b0}})
            $fatal(1, "bsd_age_arb: grant %b is not one-hot or zero", gnt);
    end
`endif
`endif

`ifdef FORMAL
`include "bsd_age_arb_props.vh"
`endif
endmodule
`default_nettype wire
