//! One module per hardware unit.
