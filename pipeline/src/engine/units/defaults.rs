//! Defaults of fields that several unit specs share.

/// Texture memory ports.
pub(super) fn ports() -> u32 {
    4
}

/// Texture memory latency in cycles.
pub(super) fn mem_latency() -> u32 {
    4
}

/// One (one datapath, one entry per clock).
pub(super) fn one() -> u32 {
    1
}
