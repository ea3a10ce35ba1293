// Saturate a signed (N+2)-bit value into [0, 2^N - 1]: `CostTable::clamp(N)`, the output clamp
// of the dot-product and combiner units (an overflow detect and an N-bit mux).
module clamp #(parameter N = 8) (
    input  signed [N+1:0] x,
    output        [N-1:0] y
);
    assign y = x[N+1] ? {N{1'b0}} : (x[N] ? {N{1'b1}} : x[N-1:0]);
endmodule
