//! Storing equal blocks once: the index of a table of distinct blocks of numbers (a cell's
//! weights in `impact-dgmpm`'s cell layouts, a point's row of shape-function weights in
//! `impact-mpm`'s total Lagrangian table). A block is keyed on a hash of its bits, and a
//! block found under that hash is confirmed bit for bit by the caller before it is shared,
//! so a collision cannot merge two blocks: every user reads exactly the block it would
//! have stored itself. The hash's quality only affects the build's speed.
use std::collections::HashMap;

/// `(hash, ordinal among the blocks of that hash) → block` of a table the caller holds.
#[derive(Debug, Default)]
pub struct DistinctBlocks {
    index: HashMap<(u64, u32), u32>,
}

impl DistinctBlocks {
    /// An empty index.
    pub fn new() -> Self {
        Self::default()
    }

    /// The block of `table` whose bits are `bits`: the first of the blocks under their hash
    /// for which `holds(table, block)` (the caller's bit-for-bit comparison) is true, or
    /// else the block `push(table)` appends (`push`'s error passed on).
    pub fn find_or_push<T, E>(
        &mut self,
        table: &mut T,
        bits: impl Iterator<Item = u64>,
        holds: impl Fn(&T, u32) -> bool,
        push: impl FnOnce(&mut T) -> Result<u32, E>,
    ) -> Result<u32, E> {
        let hash = hash_bits(bits);
        let mut ordinal = 0u32;
        loop {
            match self.index.get(&(hash, ordinal)) {
                Some(&block) if holds(table, block) => return Ok(block),
                Some(_) => ordinal += 1,
                None => {
                    let block = push(table)?;
                    self.index.insert((hash, ordinal), block);
                    return Ok(block);
                }
            }
        }
    }
}

/// A 64-bit hash of a stream of words (FxHash's step).
fn hash_bits(bits: impl Iterator<Item = u64>) -> u64 {
    bits.fold(0u64, |h, x| {
        (h.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Equal blocks share an entry, different ones do not, even under one hash.
    #[test]
    fn equal_blocks_share_and_colliding_blocks_stay_apart() {
        let blocks: [[u64; 2]; 4] = [[1, 2], [3, 4], [1, 2], [3, 4]];
        let mut table: Vec<[u64; 2]> = Vec::new();
        let mut index = DistinctBlocks::new();
        let mut rows = vec![];
        for block in blocks {
            let found = index.find_or_push(
                &mut table,
                block.iter().copied(),
                |table, b| table[b as usize] == block,
                |table| -> Result<u32, ()> {
                    table.push(block);
                    Ok(table.len() as u32 - 1)
                },
            );
            rows.push(found.unwrap());
        }
        assert_eq!(rows, [0, 1, 0, 1]);
        // a forced collision: every block under one key, told apart by `holds`
        let mut index = DistinctBlocks::new();
        let mut held: Vec<u64> = Vec::new();
        for value in [7u64, 8, 7] {
            let found = index.find_or_push(
                &mut held,
                std::iter::empty(),
                |held, b| held[b as usize] == value,
                |held| -> Result<u32, ()> {
                    held.push(value);
                    Ok(held.len() as u32 - 1)
                },
            );
            assert_eq!(
                found.unwrap() as usize,
                held.iter().position(|&v| v == value).unwrap()
            );
        }
        assert_eq!(held, [7, 8]);
    }
}
