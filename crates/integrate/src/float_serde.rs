//! A float that may be infinite, through serde: a number, or in a human-readable format (JSON, which has no
//! infinity) the strings "inf" and "-inf"; binary formats keep the bits as they are.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    if s.is_human_readable() && v.is_infinite() {
        return s.serialize_str(if *v > 0.0 { "inf" } else { "-inf" });
    }
    v.serialize(s)
}

#[derive(Deserialize)]
#[serde(untagged)]
enum NumberOrName {
    Number(f64),
    Name(String),
}

pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    if !d.is_human_readable() {
        return f64::deserialize(d);
    }
    match NumberOrName::deserialize(d)? {
        NumberOrName::Number(v) => Ok(v),
        NumberOrName::Name(n) if n == "inf" => Ok(f64::INFINITY),
        NumberOrName::Name(n) if n == "-inf" => Ok(f64::NEG_INFINITY),
        NumberOrName::Name(n) => {
            Err(serde::de::Error::custom(format!("expected a number, \"inf\" or \"-inf\", got \"{n}\"")))
        }
    }
}
