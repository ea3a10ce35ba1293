//! bumpsim pipelines: scenes, rasterizer, float reference, configs, the cycle simulator,
//! reports and traces.
pub mod animation;
pub mod artifacts;
pub mod config;
pub mod edges;
pub mod engine;
pub mod highlight;
pub mod memo;
pub mod metrics;
pub mod ndf;
pub mod nv2a;
pub mod output;
pub mod passes;
pub mod plot;
pub mod progress;
pub mod quantize;
pub mod raster;
pub mod reference;
pub mod report;
pub mod rop;
pub mod run;
pub mod scene;
#[cfg(test)]
mod scratch;
pub mod sim;
pub mod study;
pub mod sweep;
pub mod texcache;
pub mod trace;
pub mod wang;
