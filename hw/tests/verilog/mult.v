// n x m unsigned multiplier, full n+m-bit product: `CostTable::multiplier(n, m)`.
module mult #(parameter N = 8, parameter M = 8) (
    input  [N-1:0]   a,
    input  [M-1:0]   b,
    output [N+M-1:0] p
);
    assign p = a * b;
endmodule
