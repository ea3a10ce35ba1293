// n-bit unsigned squarer, full 2n-bit result: `CostTable::squarer(n)`.
//
// Written as the folded partial-product array the model assumes: a^2 = sum_i a_i 4^i
// + sum_{i<j} a_i a_j 2^(i+j+1), i.e. n(n-1)/2 AND terms plus the diagonal, about half the
// bits of an n x n multiplier. (Yosys 0.23 does not fold `a * a` by itself: that source
// synthesises to about 0.66 of a multiplier; this one to about 0.46-0.52. `yosys sat` proves
// the two equivalent for n = 8 and 12.)
module squarer #(parameter N = 8) (
    input  [N-1:0]   a,
    output [2*N-1:0] p
);
    reg [2*N-1:0] acc;
    reg [2*N-1:0] diag;
    integer i;
    always @(*) begin
        diag = {2*N{1'b0}};
        for (i = 0; i < N; i = i + 1) diag[2*i] = a[i];
        acc = diag;
        // row i: a_i * a_j for j > i, weight 2^(i+j+1)
        for (i = 0; i < N - 1; i = i + 1)
            acc = acc + ((a[i] ? ({{N{1'b0}}, a} >> (i + 1)) : {2*N{1'b0}}) << (2*i + 2));
    end
    assign p = acc;
endmodule
