//! The unit contract: what every modelled hardware block provides.
//!
//! A unit is a functional block with typed input and output ports (each a vector of 1 to 4
//! lanes of one [`Encoding`]), a pipeline latency, an initiation interval, a gate estimate
//! from its configured widths, and two evaluation modes behind one interface:
//!
//! * [`Mode::Exact`]: the algorithm in f64, without quantization. Inputs and outputs are read
//!   and written through [`Sample::x`].
//! * [`Mode::BitAccurate`]: the hardware in fixed point. Inputs and outputs are raw words in
//!   their port encodings ([`Sample::raw`]); `x` carries the decoded value for traces.
//!
//! Timing (latency, interval, valid/ready, counters, probes) is not the unit's business: the
//! clocked shell [`crate::stage::Stage`] wraps any unit and provides it, so a unit only states
//! its numbers.

use crate::columns::{Column, ColumnIn};
use crate::format::{Codec, Encoding};
use crate::frame::FrameInputs;
use crate::gates::{CostTable, GateBudget};
use crate::texture::Texture;
use std::sync::Arc;

/// Largest number of lanes a port carries (RGBA, xyz + w).
pub const MAX_LANES: usize = 4;

/// Evaluation mode of a unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Mode {
    /// The algorithm in f64: no quantization anywhere inside the unit.
    Exact,
    /// The hardware: every port and internal register holds a word of its configured format.
    BitAccurate,
}

/// One lane of a port: the real value and the raw word.
///
/// In bit-accurate mode `raw` is authoritative and `x == encoding.decode(raw)`. In exact mode
/// `x` is authoritative and `raw == encoding.encode(x)` is kept for traces only.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Sample {
    pub x: f64,
    pub raw: i64,
}

impl Sample {
    /// `x` quantized into a fixed-point encoding `enc` whose LSB is `lsb` (the caller's, once
    /// per word): the raw word by the encoding's rounding and overflow modes, and its value.
    #[inline]
    pub fn fixed(enc: &Encoding, lsb: f64, x: f64) -> Sample {
        let raw = enc.format.from_f64(x, enc.quant, enc.overflow);
        Sample {
            x: raw as f64 * lsb,
            raw,
        }
    }
}

/// The value on a port: up to [`MAX_LANES`] lanes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Word {
    pub lanes: [Sample; MAX_LANES],
}

impl Word {
    /// Real values of the first `n` lanes.
    pub fn xs<const N: usize>(&self) -> [f64; N] {
        std::array::from_fn(|i| self.lanes[i].x)
    }
    /// Raw words of the first `n` lanes.
    pub fn raws<const N: usize>(&self) -> [i64; N] {
        std::array::from_fn(|i| self.lanes[i].raw)
    }
    /// A word from real values, with raw words encoded for traces (exact mode).
    pub fn from_exact(enc: &Encoding, xs: &[f64]) -> Word {
        let mut w = Word::default();
        for (l, &x) in w.lanes.iter_mut().zip(xs) {
            *l = Sample {
                x,
                raw: enc.encode(x),
            };
        }
        w
    }
    /// A word from raw words, decoded (bit-accurate mode).
    #[inline]
    pub fn from_raw(enc: &Encoding, raws: &[i64]) -> Word {
        let mut w = Word::default();
        for (l, &raw) in w.lanes.iter_mut().zip(raws) {
            *l = Sample {
                x: enc.decode(raw),
                raw,
            };
        }
        w
    }
    /// Quantize real values into a port's encoding: the bit-accurate way to produce a word
    /// from a value computed in f64 (used at interfaces such as the attribute interpolator).
    #[inline]
    pub fn quantize(enc: &Encoding, xs: &[f64]) -> Word {
        let mut w = Word::default();
        if enc.codec == Codec::Fixed {
            // the codec's match and the scale once per word, not per lane
            let lsb = enc.format.lsb();
            for (l, &x) in w.lanes.iter_mut().zip(xs) {
                *l = Sample::fixed(enc, lsb, x);
            }
            return w;
        }
        for (l, &x) in w.lanes.iter_mut().zip(xs) {
            let raw = enc.encode(x);
            *l = Sample {
                x: enc.decode(raw),
                raw,
            };
        }
        w
    }
    /// Build a word for `mode`: exact keeps `xs`, bit-accurate quantizes them.
    pub fn for_mode(mode: Mode, enc: &Encoding, xs: &[f64]) -> Word {
        match mode {
            Mode::Exact => Word::from_exact(enc, xs),
            Mode::BitAccurate => Word::quantize(enc, xs),
        }
    }
}

/// A port: its name, its number of lanes and the encoding of each lane.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PortSpec {
    pub name: String,
    pub lanes: u8,
    pub enc: Encoding,
}

impl PortSpec {
    pub fn new(name: &str, lanes: u8, enc: Encoding) -> Self {
        assert!((1..=MAX_LANES as u8).contains(&lanes));
        PortSpec {
            name: name.to_string(),
            lanes,
            enc,
        }
    }
    /// Bits carried by the port per transfer.
    pub fn bits(&self) -> u32 {
        self.lanes as u32 * self.enc.width()
    }
}

/// A texture a unit reads: the shared texture and the texels one fragment reads of it.
#[derive(Debug, Clone)]
pub struct TextureRead {
    pub texture: Arc<Texture>,
    pub taps: u32,
}

/// A texture a unit reads in its per-frame work rather than per fragment (the palette
/// builder's environment images, Tarini et al. §5.1 item 3): it lies in the engine's texture
/// memory, not in the unit, and the report counts its bits and the texels read each frame.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameRead {
    /// What the texture holds, unique within the unit.
    pub name: String,
    pub size: [u32; 2],
    pub bits_per_texel: u32,
    /// Texels read per frame.
    pub texels_per_frame: u64,
}

/// A unit as [`std::any::Any`], so that a tool holding a `&dyn Unit` (the Verilog generators)
/// can reach the concrete unit; implemented for every `'static` type. On a `Box<dyn Unit>`
/// call it through the box (`b.as_ref().as_any()`), or it answers for the box.
pub trait AsAny {
    fn as_any(&self) -> &dyn std::any::Any;
}

impl<T: std::any::Any> AsAny for T {
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// What every hardware unit provides. See the module documentation.
pub trait Unit: Send + Sync + AsAny {
    /// The unit's kind, e.g. `"dot3"`; instance names are given by the pipeline.
    fn kind(&self) -> &'static str;
    fn inputs(&self) -> &[PortSpec];
    fn outputs(&self) -> &[PortSpec];
    /// Cycles from accepting an input to presenting its result (>= 1).
    fn latency(&self) -> u32;
    /// Cycles between two accepted inputs (>= 1); e.g. n for n lights on one datapath.
    fn interval(&self) -> u32;
    /// Gate-equivalent estimate from the configured widths, itemised.
    fn gates(&self, table: &CostTable) -> GateBudget;
    /// The estimate of the hardware the unit's Verilog generator builds (`crate::rtl`), where
    /// [`Unit::gates`] prices other hardware (the texture shaders' programmable part against
    /// their configured programs); `None` (the default): [`Unit::gates`] is that hardware.
    /// Synthesis is compared with this (`bumpsim gates --synth`).
    fn generated_gates(&self, _table: &CostTable) -> Option<GateBudget> {
        None
    }
    /// Cycles of work before each frame (table builds, LUT loads). Default none.
    fn frame_cycles(&self) -> u64 {
        0
    }
    /// The table writes of the frame work, for traces: `(clock within the unit's
    /// [`Unit::frame_cycles`], entry index, the entry as output words)`, in clock order.
    /// Default none.
    fn frame_writes(&self) -> Vec<(u64, u64, Vec<Word>)> {
        Vec::new()
    }
    /// The textures of the engine's texture memory the unit reads, and how many texels per
    /// fragment. Default none.
    fn textures(&self) -> Vec<TextureRead> {
        Vec::new()
    }
    /// The textures of the engine's texture memory the unit reads in its frame work
    /// ([`FrameRead`]). Default none.
    fn frame_reads(&self) -> Vec<FrameRead> {
        Vec::new()
    }
    /// Load the frame's inputs ([`FrameInputs`]: lights, viewer, materials) before a frame. A
    /// unit whose registers or tables follow them rebuilds them here, to exactly what a unit
    /// built for this frame holds, and pays the work in [`Unit::frame_cycles`]. Errors when
    /// the frame needs other hardware (more lights than the unit was built for). Default:
    /// nothing of the unit follows the frame.
    fn begin_frame(&mut self, _frame: &FrameInputs) -> Result<(), String> {
        Ok(())
    }
    /// The host uploaded `new` in the texture memory in place of `old` (a lighting map
    /// rebuilt for a moved light; the same size and texel format): a unit reading `old` reads
    /// `new` from now on. Default: the unit reads no texture.
    fn upload(&mut self, _old: &Arc<Texture>, _new: &Arc<Texture>) {}
    /// Whether the unit may kill fragments (CULL_FRAGMENT, clip planes). Default no.
    fn can_kill(&self) -> bool {
        false
    }
    /// For a unit that [`Unit::can_kill`]: whether the fragment whose inputs and freshly
    /// computed outputs are given survives. Called after [`Unit::eval`].
    fn live(&self, _mode: Mode, _ins: &[Word], _outs: &[Word]) -> bool {
        true
    }
    /// Compute the outputs for one set of inputs. `ins` follow [`Unit::inputs`] and `outs`
    /// follow [`Unit::outputs`].
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]);
    /// The bit-accurate datapath over a batch of `n` fragments held as columns
    /// ([`crate::columns`]): `ins[p].lanes[l][k]` is the raw word of lane `l` of input port
    /// `p` for fragment `k`; write the output ports' raw words the same way, each the one
    /// [`Unit::eval`] gives in [`Mode::BitAccurate`]. Returns `false`, writing nothing, when
    /// the unit has no batch datapath (the default): [`Unit::eval`] then runs fragment by
    /// fragment. Not called for a unit that [`Unit::can_kill`].
    fn eval_columns(&self, _n: usize, _ins: &[ColumnIn<'_>], _outs: &mut [&mut Column]) -> bool {
        false
    }
}

/// Index of a port by name, for wiring.
pub fn port_index(ports: &[PortSpec], name: &str) -> Option<usize> {
    ports.iter().position(|p| p.name == name)
}
