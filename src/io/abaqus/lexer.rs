//! Keyword lines and fields: a keyword line into its name and parameters, data lines into
//! fields (commas outside double quotes), numbers in Fortran and C notation, and names kept
//! both canonical (upper case) and as written.

use super::lines::Loc;

pub(super) struct Param {
    pub(super) key: String,
    pub(super) value: Option<String>,
    pub(super) used: bool,
}

pub(super) struct Keyword {
    /// Upper case, blanks removed: "SOLIDSECTION".
    pub(super) name: String,
    /// For messages: "*SOLID SECTION".
    pub(super) display: String,
    pub(super) params: Vec<Param>,
    pub(super) loc: Loc,
}

impl Keyword {
    pub(super) fn parse(text: &str, loc: Loc) -> Result<Keyword, String> {
        let fields = split_fields(&text[1..]);
        let words: Vec<&str> = fields[0].split_whitespace().collect();
        if words.is_empty() {
            return Err("expected a keyword after '*'".into());
        }
        let display = format!("*{}", words.join(" ").to_uppercase());
        let mut params = Vec::new();
        for field in &fields[1..] {
            if field.is_empty() {
                continue;
            }
            let (key, value) = match field.split_once('=') {
                Some((k, v)) => (k, Some(unquote(v.trim()).to_string())),
                None => (*field, None),
            };
            let key: String = key.split_whitespace().collect::<String>().to_uppercase();
            if key.is_empty() {
                return Err(format!(
                    "{display}: expected a parameter name before '=' in \"{field}\""
                ));
            }
            params.push(Param {
                key,
                value,
                used: false,
            });
        }
        Ok(Keyword {
            name: words.concat().to_uppercase(),
            display,
            params,
            loc,
        })
    }

    pub(super) fn flag(&mut self, key: &str) -> bool {
        match self.params.iter_mut().find(|p| p.key == key) {
            Some(p) => {
                p.used = true;
                true
            }
            None => false,
        }
    }

    pub(super) fn value(&mut self, key: &str) -> Result<Option<String>, String> {
        match self.params.iter_mut().find(|p| p.key == key) {
            None => Ok(None),
            Some(p) => {
                p.used = true;
                match &p.value {
                    Some(v) if !v.is_empty() => Ok(Some(v.clone())),
                    _ => Err(format!(
                        "{}: expected a value for the parameter {key} ({key}=...)",
                        self.display
                    )),
                }
            }
        }
    }

    pub(super) fn required(&mut self, key: &str) -> Result<String, String> {
        self.value(key)?.ok_or_else(|| {
            format!(
                "{}: expected the parameter {key}= (it is required)",
                self.display
            )
        })
    }
}

/// Split on commas outside double quotes, trimming each field.
fn split_fields(text: &str) -> Vec<&str> {
    if !text.contains('"') {
        return text.split(',').map(str::trim).collect();
    }
    let mut out = Vec::new();
    let (mut start, mut quoted) = (0, false);
    for (i, c) in text.char_indices() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => {
                out.push(text[start..i].trim());
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(text[start..].trim());
    out
}

/// Data fields with trailing blanks dropped ("1, 2," has two fields).
pub(super) fn data_fields(text: &str) -> Vec<&str> {
    let mut f = split_fields(text);
    while f.last() == Some(&"") {
        f.pop();
    }
    f
}

fn unquote(s: &str) -> &str {
    s.strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .unwrap_or(s)
}

/// A field that is a label rather than a name: Abaqus names start with a letter or '_'.
pub(super) fn looks_numeric(field: &str) -> bool {
    field
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_digit() || c == '+' || c == '-')
}

pub(super) fn parse_number(field: &str) -> Option<f64> {
    // Fortran writers use D exponents (1.0D+03).
    let value = if field.contains(['d', 'D']) {
        field.replace(['d', 'D'], "e").parse::<f64>()
    } else {
        field.parse::<f64>()
    };
    value.ok().filter(|x| x.is_finite())
}

/// A set, surface or material name: canonical (upper-case) and as written.
#[derive(Clone, Debug)]
pub(super) struct Name {
    pub(super) canon: String,
    pub(super) written: String,
}

impl Name {
    pub(super) fn new(written: &str) -> Name {
        let written = unquote(written.trim()).to_string();
        Name {
            canon: written.to_uppercase(),
            written,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::*;

    #[test]
    fn keywords_parameters_and_names_are_case_insensitive() {
        let text = format!(
            "*node, nset=All\n{}*Element, Type=c3d10, Elset=Body\n{}*material, name=Iron\n\
             *elastic, type=Isotropic\n100e9, 0.25\n*density\n7000\n\
             *Solid Section, elset=BODY, material=iron\n*boundary\nall, 1, 3\n\
             *node Print\n*NSET,\n    NSET=Continued\nALL\n",
            unit_tet_nodes(11),
            unit_tet_element(7, 11)
        );
        let deck = read_text("case", &text).unwrap();
        assert_eq!(deck.mesh.parts[0].name, "BODY");
        assert_eq!(deck.mesh.parts[0].material.as_deref(), Some("IRON"));
        assert_eq!(deck.mesh.materials["IRON"].young, 100e9);
        assert_eq!(deck.boundaries[0].nodes.len(), 10);
        assert_eq!(deck.mesh.node_sets["CONTINUED"].len(), 10);
        assert_eq!(deck.warnings.len(), 1, "{:?}", deck.warnings);
        assert!(
            deck.warnings[0].contains("*NODE PRINT (1x"),
            "{:?}",
            deck.warnings
        );
    }

    #[test]
    fn numbers_in_fortran_and_c_notation() {
        for (s, v) in [
            ("1.", 1.0),
            ("1.e5", 1e5),
            (".5", 0.5),
            ("2.1D+11", 2.1e11),
            ("-3d-2", -0.03),
        ] {
            assert_eq!(parse_number(s), Some(v), "{s}");
        }
        for s in ["nan", "inf", "1.2.3", "", "x"] {
            assert_eq!(parse_number(s), None, "{s}");
        }
    }
}
