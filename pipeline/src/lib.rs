//! bumpsim pipelines: scenes, rasterizer, float reference, configs, the cycle simulator,
//! reports and traces.
pub mod scene;
