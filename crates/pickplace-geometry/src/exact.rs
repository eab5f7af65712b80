//! Fixed-length arrays read exactly (scenes, gripper files): serde's `[T; N]` takes the first N values of a longer
//! array and drops the rest, so a 4-value position or a 6-value quaternion would be read as
//! something the user did not write.

use crate::math::Real;
use serde::de::{Deserializer, Error as _, IgnoredAny, SeqAccess, Visitor};
use std::fmt;

/// Exactly `N` numbers, named `field` in errors with their `meaning` (`"[x, y, z]"`): the
/// body of a `deserialize_with` function.
///
/// # Errors
/// The deserializer's error naming `field`, the count expected and the count given.
pub fn array<'de, D: Deserializer<'de>, const N: usize>(
    d: D,
    field: &'static str,
    meaning: &'static str,
) -> Result<[Real; N], D::Error> {
    d.deserialize_seq(Exact::<N>(field, meaning))
}

/// An optional `[x, y, z]` named `field` in errors: the body of a `deserialize_with`
/// function of an `Option<[Real; 3]>` field (with `#[serde(default)]`).
///
/// # Errors
/// As [`array`].
pub fn optional_xyz<'de, D: Deserializer<'de>>(
    d: D,
    field: &'static str,
) -> Result<Option<[Real; 3]>, D::Error> {
    /// The array, for `Option`'s own handling of an absent value.
    struct Xyz([Real; 3]);
    /// The field's name, carried into the array's deserializer.
    struct Named(&'static str);
    impl<'de> serde::de::DeserializeSeed<'de> for Named {
        type Value = Xyz;
        fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Xyz, D::Error> {
            d.deserialize_seq(Exact::<3>(self.0, "[x, y, z]")).map(Xyz)
        }
    }
    /// `Option` handling with a seed: `None` for a unit or absent value.
    struct OptionOf(&'static str);
    impl<'de> Visitor<'de> for OptionOf {
        type Value = Option<Xyz>;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            write!(f, "{}: exactly 3 numbers [x, y, z]", self.0)
        }
        fn visit_none<E: serde::de::Error>(self) -> Result<Self::Value, E> {
            Ok(None)
        }
        fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
            serde::de::DeserializeSeed::deserialize(Named(self.0), d).map(Some)
        }
    }
    Ok(d.deserialize_option(OptionOf(field))?.map(|x| x.0))
}

/// Reads exactly N numbers; the field's name and the numbers' meaning are in the error.
struct Exact<const N: usize>(&'static str, &'static str);

impl<'de, const N: usize> Visitor<'de> for Exact<N> {
    type Value = [Real; N];

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: exactly {N} numbers {}", self.0, self.1)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut values = [0.0; N];
        let mut count = 0;
        while let Some(v) = seq.next_element::<Real>()? {
            if count < N {
                values[count] = v;
            }
            count += 1;
            if count > N {
                // Count the rest without keeping it.
                while seq.next_element::<IgnoredAny>()?.is_some() {
                    count += 1;
                }
            }
        }
        if count == N {
            Ok(values)
        } else {
            Err(A::Error::custom(format!(
                "{}: expected exactly {N} numbers {}, got {count}",
                self.0, self.1
            )))
        }
    }
}
