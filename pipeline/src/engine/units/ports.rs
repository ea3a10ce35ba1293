//! Port names and lookups shared by the unit specs.

use bumpsim_hw::PortSpec;
use std::collections::BTreeMap;

/// `prefix0`, `prefix1`, ... `prefix{n-1}`.
pub(super) fn seq(prefix: &str, n: u32) -> Vec<String> {
    (0..n).map(|i| format!("{prefix}{i}")).collect()
}

/// The signal wired to input `name`.
pub(super) fn input<'a>(
    ins: &'a BTreeMap<String, PortSpec>,
    name: &str,
) -> Result<&'a PortSpec, String> {
    ins.get(name)
        .ok_or_else(|| format!("input {name:?} is not wired"))
}
