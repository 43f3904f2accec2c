//! The small XML vocabulary the model descriptions and the SSP files are written with
//! (the SSP writer in fmu-build uses it too): escaped attribute values and reals as
//! xs:double. The documents themselves are written line by line with `writeln!`, so that
//! their layout is visible in the code that writes them.

/// Escapes text for an XML attribute value (or element text): `&`, `<`, `>` and `"`.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

/// A Real as xs:double: Rust's shortest representation that reads back exactly.
pub fn real(value: f64) -> String {
    format!("{value:?}")
}

/// ` name="value"`, the value escaped: an attribute to append to an element's head.
pub fn attribute(name: &str, value: &str) -> String {
    format!(r#" {name}="{}""#, escape(value))
}

/// [`attribute`] if there is a value, nothing otherwise.
pub fn optional_attribute(name: &str, value: Option<&str>) -> String {
    value.map(|v| attribute(name, v)).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escaping_and_reals() {
        assert_eq!(escape(r#"a<b & "c">"#), "a&lt;b &amp; &quot;c&quot;&gt;");
        assert_eq!(real(2.0), "2.0");
        assert_eq!(real(5e-5), "5e-5");
        assert_eq!(real(0.1).parse::<f64>().unwrap(), 0.1);
    }

    #[test]
    fn attributes_are_escaped_and_optional() {
        assert_eq!(attribute("unit", "N<m"), r#" unit="N&lt;m""#);
        assert_eq!(optional_attribute("unit", Some("m/s")), r#" unit="m/s""#);
        assert_eq!(optional_attribute("unit", None), "");
    }
}
