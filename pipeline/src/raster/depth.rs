//! The early depth test: a depth buffer of quantised window depths, cleared to the largest
//! code, compare function LESS. Rows are allocated when first touched so that a large, mostly
//! empty image does not cost a full buffer.

/// Depth buffer for a `width` x `height` image.
#[derive(Debug, Clone)]
pub struct DepthBuffer {
    width: u32,
    clear: u32,
    rows: Vec<Option<Box<[u32]>>>,
}

impl DepthBuffer {
    pub fn new(width: u32, height: u32, clear: u32) -> DepthBuffer {
        DepthBuffer {
            width,
            clear,
            rows: vec![None; height as usize],
        }
    }

    /// Depth test LESS at (x, y): on pass the buffer is updated and `true` returned.
    /// Out-of-range coordinates fail.
    pub fn test_and_set(&mut self, x: u32, y: u32, depth: u32) -> bool {
        if x >= self.width {
            return false;
        }
        let Some(row) = self.rows.get_mut(y as usize) else {
            return false;
        };
        let row =
            row.get_or_insert_with(|| vec![self.clear; self.width as usize].into_boxed_slice());
        let cell = &mut row[x as usize];
        if depth < *cell {
            *cell = depth;
            true
        } else {
            false
        }
    }

    /// Stored depth at (x, y) (the clear value when untouched or out of range).
    pub fn get(&self, x: u32, y: u32) -> u32 {
        match self.rows.get(y as usize) {
            Some(Some(row)) => row.get(x as usize).copied().unwrap_or(self.clear),
            _ => self.clear,
        }
    }
}
