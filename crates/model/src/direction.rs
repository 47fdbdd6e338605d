//! [`Direction`]: a vector written `(x, y, z)` (a tuple, the vehicle syntax of issue 13) or
//! `[x, y, z]` (a list, as [`V3`] is written), 2 or 3 numbers; stored with z = 0 in 2D.

use std::fmt;

use serde::de::{self, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::scene::V3;

/// A direction or point written as a tuple or a list of 2 or 3 numbers.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Direction(pub V3);

impl Direction {
    /// As a nalgebra vector.
    pub fn vec(&self) -> nalgebra::Vector3<f64> {
        self.0.vec()
    }
}

impl Serialize for Direction {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

struct Numbers;

impl<'de> Visitor<'de> for Numbers {
    type Value = Direction;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a vector of 2 or 3 numbers, `(x, y, z)` or `[x, y, z]`")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Direction, A::Error> {
        let mut v = Vec::with_capacity(3);
        while let Some(x) = seq.next_element::<f64>()? {
            v.push(x);
        }
        V3::try_from(v).map(Direction).map_err(de::Error::custom)
    }
}

impl<'de> Deserialize<'de> for Direction {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Direction, D::Error> {
        d.deserialize_any(Numbers)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_direction_is_read_from_a_tuple_or_a_list() {
        let t: Direction = ron::from_str("(0.0, 0.0, -1.0)").unwrap();
        let l: Direction = ron::from_str("[0.0, 0.0, -1.0]").unwrap();
        let p: Direction = ron::from_str("(1.0, 2.0)").unwrap();
        assert_eq!(t, l);
        assert_eq!(t.0.0, [0.0, 0.0, -1.0]);
        assert_eq!(p.0.0, [1.0, 2.0, 0.0]);
        let e = ron::from_str::<Direction>("(1.0,)")
            .unwrap_err()
            .to_string();
        assert!(e.contains("2 or 3 numbers"), "{e}");
        let j = serde_json::to_string(&t).unwrap();
        assert_eq!(serde_json::from_str::<Direction>(&j).unwrap(), t);
    }
}
