//! Fixed-length arrays read exactly: serde's `[T; N]` takes the first N values of a longer
//! array and drops the rest, so a 4-value position or a 6-value quaternion would be read as
//! something the user did not write.

use pickplace_geometry::math::Real;
use serde::de::{Deserializer, Error as _, IgnoredAny, SeqAccess, Visitor};
use std::fmt;

/// A pose's `position = [x, y, z]`.
pub fn position<'de, D: Deserializer<'de>>(d: D) -> Result<[Real; 3], D::Error> {
    d.deserialize_seq(Exact::<3>("position", "[x, y, z]"))
}

/// `target.point = [x, y, z]`.
pub fn point<'de, D: Deserializer<'de>>(d: D) -> Result<[Real; 3], D::Error> {
    d.deserialize_seq(Exact::<3>("point", "[x, y, z]"))
}

/// A pose's `orientation = [x, y, z, w]`.
pub fn quaternion<'de, D: Deserializer<'de>>(d: D) -> Result<[Real; 4], D::Error> {
    d.deserialize_seq(Exact::<4>("orientation", "[x, y, z, w]"))
}

/// `object.center_of_gravity = [x, y, z]`, optional.
pub fn optional_xyz<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[Real; 3]>, D::Error> {
    optional_exact3(d, "center_of_gravity")
}

/// The gripper overrides' `tool_offset = [x, y, z]`, optional.
pub(crate) fn optional_tool_offset<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<[Real; 3]>, D::Error> {
    optional_exact3(d, "tool_offset")
}

/// The gripper overrides' `approach_axis = [x, y, z]`, optional.
pub(crate) fn optional_approach_axis<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<[Real; 3]>, D::Error> {
    optional_exact3(d, "approach_axis")
}

/// The gripper overrides' `closing_axis = [x, y, z]`, optional.
pub(crate) fn optional_closing_axis<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<[Real; 3]>, D::Error> {
    optional_exact3(d, "closing_axis")
}

/// An optional `[x, y, z]` named `field` in errors.
fn optional_exact3<'de, D: Deserializer<'de>>(
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
