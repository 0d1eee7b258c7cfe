//! Keys that take one number or a list of them: a 2D body's `rotation` (an angle) and
//! a 2D plane's `half_extent` (one half-width) may be written as a bare number, as
//! docs/scenes.md gives them, or as a one-element list.

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use std::fmt;

struct Numbers;

impl<'de> Visitor<'de> for Numbers {
    type Value = Vec<f64>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number or a list of numbers")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Vec<f64>, E> {
        Ok(vec![v])
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Vec<f64>, E> {
        Ok(vec![v as f64])
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Vec<f64>, E> {
        Ok(vec![v as f64])
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<f64>, A::Error> {
        let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(16));
        while let Some(x) = seq.next_element::<f64>()? {
            out.push(x);
        }
        Ok(out)
    }
}

/// One number or a list of numbers, as a list.
pub fn numbers<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
    d.deserialize_any(Numbers)
}

/// [`numbers`] for an optional key (with `#[serde(default)]`).
pub fn some_numbers<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec<f64>>, D::Error> {
    numbers(d).map(Some)
}

#[cfg(test)]
mod tests {
    #[derive(serde::Deserialize)]
    struct T {
        #[serde(deserialize_with = "super::numbers")]
        a: Vec<f64>,
        #[serde(default, deserialize_with = "super::some_numbers")]
        b: Option<Vec<f64>>,
    }

    #[test]
    fn a_bare_number_is_a_list_of_one() {
        let t: T = toml::from_str("a = 30\nb = 0.5").unwrap();
        assert_eq!((t.a, t.b), (vec![30.0], Some(vec![0.5])));
        let t: T = toml::from_str("a = [1.0, 2]").unwrap();
        assert_eq!((t.a, t.b), (vec![1.0, 2.0], None));
        let e = toml::from_str::<T>("a = \"x\"").err().unwrap().to_string();
        assert!(e.contains("a number or a list of numbers"), "{e}");
    }
}
