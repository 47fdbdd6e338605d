//! A small deterministic pseudo-random generator (SplitMix64): the same seed gives the same
//! mutants on every machine and every version of the dependencies.

/// SplitMix64 (Steele, Lea and Flood 2014): 64-bit state, one addition and a mix per draw.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
}

impl Rng {
    /// A generator for the mutant `index` of the campaign `seed`: independent of the order
    /// in which the workers take the mutants.
    pub fn for_mutant(seed: u64, index: u64) -> Rng {
        let mut base = Rng { state: seed };
        let s = base.next_u64() ^ index.wrapping_mul(0xD1B5_4A32_D192_ED03);
        Rng { state: s }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform integer in `0..n` (`n` > 0).
    pub fn below(&mut self, n: usize) -> usize {
        assert!(n > 0, "Rng::below(0)");
        (self.next_u64() % n as u64) as usize
    }

    /// One element of a non-empty slice.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }

    /// True with probability `numerator / denominator`.
    pub fn chance(&mut self, numerator: usize, denominator: usize) -> bool {
        self.below(denominator) < numerator
    }
}

/// FNV-1a 64-bit hash: names the reproducer files after their content.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_and_index_give_the_same_draws_and_other_indices_differ() {
        let draws = |seed, index| {
            let mut r = Rng::for_mutant(seed, index);
            (0..8).map(|_| r.next_u64()).collect::<Vec<_>>()
        };
        assert_eq!(draws(7, 3), draws(7, 3));
        assert_ne!(draws(7, 3), draws(7, 4));
        assert_ne!(draws(7, 3), draws(8, 3));
    }

    #[test]
    fn below_stays_in_range() {
        let mut r = Rng::for_mutant(1, 1);
        for n in 1..50 {
            assert!(r.below(n) < n);
        }
    }
}
