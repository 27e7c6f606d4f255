// SPDX-License-Identifier: Apache-2.0
// A toy toplevel for the runner's own tests (tb/runner/test_runner.py).
`default_nettype none
module runner_dut (
    input  wire       clk,
    input  wire       rst,
    output reg  [3:0] count_q
);
    always @(posedge clk) begin
        count_q <= count_q + 4'd1;
        if (rst) count_q <= 4'd0;
    end
endmodule
`default_nettype wire
