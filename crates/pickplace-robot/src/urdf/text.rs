//! The URDF's text checked against size and depth limits before urdf-rs parses it.

/// Deepest element nesting a URDF may have (a real one nests 4 or 5 deep). urdf-rs parses
/// recursively: a deeper document (a hostile 1.4 MB file of nested elements) would overflow
/// the stack and abort, so the text is scanned for its depth before it is parsed.
pub const MAX_XML_DEPTH: usize = 256;
/// Most `<link>` elements a URDF may have (the largest shipped robots have about 100).
pub const MAX_LINKS: usize = 10_000;
/// Most `<joint>` elements a URDF may have (children of `<robot>`).
pub const MAX_JOINTS: usize = 10_000;
/// Longest attribute value other than a name (bytes): file names, vectors, references.
pub const MAX_ATTRIBUTE_BYTES: usize = pickplace_geometry::io::MAX_PATH_BYTES;

/// What [`scan`] found beyond a limit.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum TextProblem {
    /// Elements nested deeper than the limit.
    TooDeep,
    /// More `<link>` or `<joint>` elements than [`MAX_LINKS`] or [`MAX_JOINTS`].
    TooMany { element: &'static str, limit: usize },
    /// An attribute value over its limit ([`pickplace_geometry::io::MAX_NAME_BYTES`] for
    /// `name`, [`MAX_ATTRIBUTE_BYTES`] for the others).
    LongValue {
        attribute: String,
        bytes: usize,
        limit: usize,
    },
}

impl std::fmt::Display for TextProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::TooDeep => write!(f, "elements nested more than {MAX_XML_DEPTH} deep"),
            Self::TooMany { element, limit } => {
                write!(f, "more than {limit} <{element}> elements")
            }
            Self::LongValue {
                attribute,
                bytes,
                limit,
            } => write!(
                f,
                "a {attribute:?} attribute is {bytes} bytes, over the limit of {limit}"
            ),
        }
    }
}

/// Checks a URDF's text against the limits before urdf-rs parses it (it copies every value
/// and recurses into every element): `Some(message)` with the line of the first problem.
pub(crate) fn check_text(text: &str) -> Option<String> {
    scan(text, MAX_XML_DEPTH).map(|(line, problem)| match problem {
        // The words of the first of these limits, which tests and users know.
        TextProblem::TooDeep => format!(
            "elements nested more than {MAX_XML_DEPTH} deep at line {line} (MAX_XML_DEPTH): refused before parsing"
        ),
        _ => format!("line {line}: {problem}: refused before parsing"),
    })
}

/// Where `text` nests elements deeper than `limit`: the 1-based line of the first element
/// beyond it.
#[cfg(test)]
pub(crate) fn too_deep(text: &str, limit: usize) -> Option<usize> {
    match scan(text, limit) {
        Some((line, TextProblem::TooDeep)) => Some(line),
        _ => None,
    }
}

/// The attributes of a start tag's inside (after the element name): names and values.
fn attributes(mut s: &[u8]) -> Vec<(&[u8], &[u8])> {
    let skip_space = |s: &[u8]| s.iter().take_while(|c| c.is_ascii_whitespace()).count();
    let mut out = Vec::new();
    loop {
        s = &s[skip_space(s)..];
        let n = s
            .iter()
            .take_while(|&&c| !c.is_ascii_whitespace() && !matches!(c, b'=' | b'/' | b'>'))
            .count();
        if n == 0 {
            return out;
        }
        let name = &s[..n];
        s = &s[n..];
        s = &s[skip_space(s)..];
        if s.first() != Some(&b'=') {
            continue;
        }
        s = &s[1..];
        s = &s[skip_space(s)..];
        let Some(&quote) = s.first().filter(|q| matches!(q, b'"' | b'\'')) else {
            return out;
        };
        let Some(len) = s[1..].iter().position(|&c| c == quote) else {
            return out;
        };
        out.push((name, &s[1..1 + len]));
        s = &s[len + 2..];
    }
}

/// The first limit `text` breaks, with its 1-based line: nesting deeper than `depth_limit`,
/// too many links or joints, an attribute value too long. A cheap scan of the tags
/// (comments, CDATA, processing instructions and declarations skipped, quoted attribute
/// values honoured); a malformed document is left to the parser to report.
fn scan(text: &str, depth_limit: usize) -> Option<(usize, TextProblem)> {
    let bytes = text.as_bytes();
    let find = |from: usize, pattern: &[u8]| -> Option<usize> {
        bytes
            .get(from..)?
            .windows(pattern.len())
            .position(|w| w == pattern)
            .map(|p| from + p + pattern.len())
    };
    let line_of = |at: usize| 1 + bytes[..at].iter().filter(|&&c| c == b'\n').count();
    let mut depth = 0usize;
    let (mut links, mut joints) = (0usize, 0usize);
    let mut i = 0;
    while let Some(offset) = bytes
        .get(i..)
        .and_then(|b| b.iter().position(|&c| c == b'<'))
    {
        let start = i + offset;
        let rest = &bytes[start..];
        let end = if rest.starts_with(b"<!--") {
            find(start, b"-->")
        } else if rest.starts_with(b"<![CDATA[") {
            find(start, b"]]>")
        } else if rest.starts_with(b"<?") {
            find(start, b"?>")
        } else if rest.starts_with(b"<!") {
            find(start, b">")
        } else if rest.starts_with(b"</") {
            depth = depth.saturating_sub(1);
            find(start, b">")
        } else {
            // A start tag: to its `>`, outside quoted attribute values.
            let mut quote = None;
            let mut close = None;
            for (k, &c) in rest.iter().enumerate().skip(1) {
                match (quote, c) {
                    (Some(q), c) if c == q => quote = None,
                    (Some(_), _) => {}
                    (None, b'"' | b'\'') => quote = Some(c),
                    (None, b'>') => {
                        close = Some(k);
                        break;
                    }
                    _ => {}
                }
            }
            if let Some(k) = close {
                let inside = &rest[1..k];
                let name_len = inside
                    .iter()
                    .take_while(|&&c| !c.is_ascii_whitespace() && !matches!(c, b'/' | b'>'))
                    .count();
                // Links and joints of the robot (a `<transmission>` names joints too).
                if depth == 1 {
                    let (count, element, limit) = match &inside[..name_len] {
                        b"link" => (&mut links, "link", MAX_LINKS),
                        b"joint" => (&mut joints, "joint", MAX_JOINTS),
                        _ => (&mut 0, "", usize::MAX),
                    };
                    *count += 1;
                    if *count > limit {
                        return Some((line_of(start), TextProblem::TooMany { element, limit }));
                    }
                }
                for (attribute, value) in attributes(&inside[name_len..]) {
                    let limit = if attribute == b"name" {
                        pickplace_geometry::io::MAX_NAME_BYTES
                    } else {
                        MAX_ATTRIBUTE_BYTES
                    };
                    if value.len() > limit {
                        return Some((
                            line_of(start),
                            TextProblem::LongValue {
                                attribute: String::from_utf8_lossy(attribute).into_owned(),
                                bytes: value.len(),
                                limit,
                            },
                        ));
                    }
                }
                if rest[k - 1] != b'/' {
                    depth += 1;
                }
            }
            close.map(|k| start + k + 1)
        };
        if depth > depth_limit {
            return Some((line_of(start), TextProblem::TooDeep));
        }
        match end {
            Some(end) => i = end,
            None => return None,
        }
    }
    None
}

#[cfg(test)]
mod depth_tests {
    use super::*;
    use crate::model::{LoadOptions, RobotModel};
    use std::path::Path;

    fn nested(depth: usize) -> String {
        format!(
            "<?xml version=\"1.0\"?>\n<!-- <a><a><a> -->\n<robot name=\"r\" note=\"a>b\">{}{}</robot>\n",
            "<a>".repeat(depth),
            "</a>".repeat(depth)
        )
    }

    #[test]
    fn nesting_beyond_the_limit_is_found_with_its_line() {
        assert_eq!(too_deep(&nested(MAX_XML_DEPTH - 1), MAX_XML_DEPTH), None);
        assert_eq!(too_deep(&nested(MAX_XML_DEPTH), MAX_XML_DEPTH), Some(3));
        // Siblings, self-closing tags, comments and CDATA add no depth.
        let flat = format!(
            "<robot>{}<![CDATA[<a><a>]]><link name='x'/></robot>",
            "<link name=\"l\"><visual/></link>".repeat(10_000)
        );
        assert_eq!(too_deep(&flat, 3), None);
        // Unterminated text is the parser's to report.
        assert_eq!(too_deep("<robot><a", 1), None);
    }

    #[test]
    fn too_many_links_and_long_names_are_refused_before_parsing() {
        // Regression (issue 18): a 100 MB name used 3 GB in urdf-rs.
        let long = format!(
            "<robot name=\"r\">\n<link name=\"{}\"/>\n</robot>",
            "n".repeat(2000)
        );
        let e = RobotModel::from_urdf_str(&long, Path::new("."), &LoadOptions::default())
            .expect_err("long name");
        assert!(
            e.to_string()
                .contains("line 2: a \"name\" attribute is 2000 bytes, over the limit of 1024"),
            "{e}"
        );
        let links = format!(
            "<robot name=\"r\">{}</robot>",
            "<link name=\"l\"/>".repeat(MAX_LINKS + 1)
        );
        assert_eq!(
            scan(&links, MAX_XML_DEPTH),
            Some((
                1,
                TextProblem::TooMany {
                    element: "link",
                    limit: MAX_LINKS
                }
            ))
        );
        let joints = format!(
            "<robot name=\"r\">\n{}</robot>",
            "<joint name=\"j\" type=\"fixed\"/>".repeat(MAX_JOINTS + 1)
        );
        assert!(check_text(&joints).is_some_and(|m| m.contains("more than 10000 <joint>")));
        // Joints named inside transmissions are not robot joints.
        let transmissions = format!(
            "<robot name=\"r\">{}</robot>",
            "<transmission><joint name=\"j\"/></transmission>".repeat(MAX_JOINTS + 1)
        );
        assert_eq!(check_text(&transmissions), None);
        let path = format!(
            "<robot name=\"r\"><link name=\"l\"><visual><geometry><mesh filename='{}'/></geometry></visual></link></robot>",
            "p".repeat(MAX_ATTRIBUTE_BYTES + 1)
        );
        assert!(
            check_text(&path).is_some_and(|m| m.contains("\"filename\" attribute is 4097 bytes"))
        );
        assert_eq!(
            attributes(b" a = '1' b=\"x y\" c /"),
            vec![(&b"a"[..], &b"1"[..]), (&b"b"[..], &b"x y"[..])]
        );
    }

    #[test]
    fn a_deeply_nested_urdf_is_refused_before_parsing() {
        // 200 000 levels overflowed urdf-rs's stack (issue 18).
        let text = nested(200_000);
        let e = RobotModel::from_urdf_str(&text, Path::new("."), &LoadOptions::default())
            .expect_err("too deep");
        let message = e.to_string();
        assert!(message.contains("MAX_XML_DEPTH"), "{message}");
        assert!(message.contains("line 3"), "{message}");
    }
}
