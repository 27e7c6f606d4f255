// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_event_timer (included at the end of the module under `ifdef FORMAL).
// The counts never wrap (count <= elapsed <= 65 534 while running), a completed
// measurement's result is at least 1, a timeout (with no completion on that clock) gives
// exactly 0, and the result holds while the timer is not running. The cover task
// (define F_ANYSTATE) starts from any state that meets the invariants instead of from
// reset, so that it reaches the timeout without 65 535 ticks.
    reg        f_past_valid = 1'b0;
    reg        f_rst_q, f_running_q, f_complete_q, f_timeout_q;
    reg [15:0] f_result_q;

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q      <= rst;
        f_running_q  <= running_q;
        f_complete_q <= complete;
        f_timeout_q  <= timeout;
        f_result_q   <= result_q;
    end

    // The invariants of a running timer.
    wire f_inv = !running_q || (elapsed_q <= LAST_BEFORE && count_q <= elapsed_q
                                && at_last_q == (elapsed_q == LAST_BEFORE)
                                && count_zero_q == (count_q == 16'd0));

    always @(*) begin
`ifdef F_ANYSTATE
        if (!f_past_valid) assume(!rst && f_inv);
`else
        if (!f_past_valid) assume(rst);
`endif
        if (f_past_valid && !f_rst_q) begin
            assert(f_inv);
            if (f_complete_q) assert(result_q != 16'd0);     // completed: never 0
            if (f_timeout_q && !f_complete_q) assert(result_q == 16'd0);  // timeout: exactly 0
            if (!f_running_q) assert(result_q == f_result_q);  // held
            if (f_complete_q || f_timeout_q) assert(!running_q);
        end
    end

    always @(*) if (f_past_valid && !rst && !f_rst_q) begin
        cover(f_timeout_q && !f_complete_q && host_req_q);
        cover(f_complete_q && result_q == 16'd1 && mode_q);       // width mode, shortest
        cover(f_complete_q && result_q == 16'hFFFF);              // completes on the last tick
        cover(f_complete_q && result_q == 16'd3 && !mode_q);      // edge mode
    end
