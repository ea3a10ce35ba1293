//! bumpsim-hw: the unit library. Number formats, the clocked-unit contract, the gate-cost
//! model, and one module per hardware unit. Knows nothing of scenes or configs.

pub mod arith;
pub mod columns;
pub mod format;
pub mod frame;
pub mod gates;
pub mod rtl;
pub mod sampler;
pub mod stage;
pub mod texture;
pub mod unit;
pub mod units;

pub use columns::{Column, ColumnIn, Columns, BATCH};
pub use format::{Codec, Encoding, Format, Overflow, Quant};
pub use frame::{FrameInputs, FrameLight, FrameMaterial};
pub use gates::{CostTable, GateBudget};
pub use sampler::{Address, Filter, Sampler};
pub use stage::{ColumnScratch, Counters, CycleState, Fifo, Probe, Scratch, Stage, Token, Wire};
pub use texture::{Texels, Texture};
pub use unit::{AsAny, FrameRead, Mode, PortSpec, Sample, TextureRead, Unit, Word, MAX_LANES};
