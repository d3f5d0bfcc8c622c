//! Test helpers: a well-formedness check of XML and counts of SVG elements.

/// Deterministic pseudo-random numbers in [0, 1) (64-bit LCG, Knuth's MMIX constants), so
/// the tests see the same inputs every run.
pub struct Lcg(pub u64);
impl Lcg {
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The tags (text between `<` and `>`) of the elements named `name`.
pub fn tags<'a>(svg: &'a str, name: &'a str) -> impl Iterator<Item = &'a str> + 'a {
    svg.split('<')
        .filter_map(|t| t.split_once('>').map(|(tag, _)| tag))
        .filter(move |tag| {
            tag.strip_prefix(name)
                .is_some_and(|rest| rest.starts_with([' ', '/']) || rest.is_empty())
        })
}

pub fn circles(svg: &str) -> impl Iterator<Item = &str> {
    tags(svg, "circle")
}

/// The markers outlined as unstable: black-stroked circles, less the legend's sample.
pub fn unstable_markers(svg: &str) -> usize {
    circles(svg)
        .filter(|c| c.contains("fill=\"none\" stroke=\"#000000\" stroke-width=\"2\""))
        .count()
        .saturating_sub(1)
}

/// The text of every `<text>` element, trimmed.
pub fn texts(svg: &str) -> Vec<&str> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| t.split_once('>'))
        .map(|(_, rest)| rest.split("</text>").next().unwrap_or("").trim())
        .collect()
}

/// A minimal XML well-formedness check: one root element, balanced and properly nested
/// tags, attributes quoted and unique, `&` only in entities, no `<` in text or values,
/// no text outside the root. Returns the number of elements.
pub fn check_xml(doc: &str) -> Result<usize, String> {
    fn check_chars(text: &str, what: &str) -> Result<(), String> {
        if text.contains('<') {
            return Err(format!("raw '<' in {what}: {text:?}"));
        }
        let mut rest = text;
        while let Some(i) = rest.find('&') {
            rest = &rest[i + 1..];
            let end = rest
                .find(';')
                .ok_or_else(|| format!("unterminated entity in {what}"))?;
            let entity = &rest[..end];
            let ok = ["amp", "lt", "gt", "quot", "apos"].contains(&entity)
                || entity
                    .strip_prefix("#x")
                    .is_some_and(|h| !h.is_empty() && h.chars().all(|c| c.is_ascii_hexdigit()))
                || entity
                    .strip_prefix('#')
                    .is_some_and(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()));
            if !ok {
                return Err(format!("bad entity &{entity}; in {what}"));
            }
        }
        if text
            .chars()
            .any(|c| (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r'))
        {
            return Err(format!("control character in {what}"));
        }
        Ok(())
    }
    let is_name = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | ':' | '.');
    let mut rest = doc;
    if let Some(r) = rest.strip_prefix("<?xml") {
        rest = &r[r.find("?>").ok_or("unterminated XML declaration")? + 2..];
    }
    let mut stack: Vec<&str> = Vec::new();
    let (mut roots, mut elements) = (0, 0);
    loop {
        let lt = rest.find('<').unwrap_or(rest.len());
        let text = &rest[..lt];
        check_chars(text, "text")?;
        if stack.is_empty() && !text.trim().is_empty() {
            return Err(format!("text outside the root: {text:?}"));
        }
        rest = &rest[lt..];
        if rest.is_empty() {
            break;
        }
        if let Some(r) = rest.strip_prefix("<!--") {
            rest = &r[r.find("-->").ok_or("unterminated comment")? + 3..];
        } else if let Some(r) = rest.strip_prefix("</") {
            let end = r.find('>').ok_or("unterminated end tag")?;
            let name = r[..end].trim_end();
            match stack.pop() {
                Some(open) if open == name => {}
                other => return Err(format!("</{name}> closes {other:?}")),
            }
            rest = &r[end + 1..];
        } else {
            let r = &rest[1..];
            let name_end = r.find(|c: char| !is_name(c)).unwrap_or(r.len());
            let name = &r[..name_end];
            if name.is_empty() {
                return Err("element without a name".into());
            }
            if stack.is_empty() {
                roots += 1;
            }
            elements += 1;
            let mut r = &r[name_end..];
            let mut attributes = Vec::new();
            loop {
                let trimmed = r.trim_start();
                let had_space = trimmed.len() < r.len();
                r = trimmed;
                if let Some(after) = r.strip_prefix("/>") {
                    r = after;
                    break;
                }
                if let Some(after) = r.strip_prefix('>') {
                    stack.push(name);
                    r = after;
                    break;
                }
                if !had_space {
                    return Err(format!("<{name}>: attributes must be separated by space"));
                }
                let attr_end = r.find(|c: char| !is_name(c)).unwrap_or(r.len());
                let attr = &r[..attr_end];
                if attr.is_empty() {
                    return Err(format!(
                        "<{name}>: bad attribute at {:?}",
                        &r[..r.len().min(20)]
                    ));
                }
                if attributes.contains(&attr) {
                    return Err(format!("<{name}>: attribute {attr} twice"));
                }
                attributes.push(attr);
                let after = r[attr_end..]
                    .strip_prefix("=\"")
                    .ok_or_else(|| format!("<{name}>: attribute {attr} not quoted"))?;
                let close = after
                    .find('"')
                    .ok_or_else(|| format!("<{name}>: unterminated {attr}"))?;
                check_chars(&after[..close], attr)?;
                r = &after[close + 1..];
            }
            rest = r;
        }
    }
    if let Some(open) = stack.last() {
        return Err(format!("<{open}> never closed"));
    }
    if roots != 1 {
        return Err(format!("{roots} root elements"));
    }
    Ok(elements)
}
