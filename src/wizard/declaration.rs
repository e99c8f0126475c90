//! A wizard's declaration: the `//!` lines at the top of its script (doc
//! and `@param name [= default] doc` lines), and the signature shown to
//! users. Plain text in, plain data out; no Rhai here.

/// A parameter's default value, as written.
#[derive(Clone, Debug, PartialEq)]
pub enum Default {
    Number(f64),
    Str(String),
    Bool(bool),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    pub name: String,
    pub default: Option<Default>,
    pub doc: String,
}

#[derive(Clone, Debug, PartialEq, Default)]
pub struct Declaration {
    /// Doc lines; the first is the one-line summary.
    pub doc: Vec<String>,
    pub params: Vec<Param>,
}

/// A `//!` line that could not be read, with its 1-based line number.
#[derive(Clone, Debug, PartialEq)]
pub struct DeclarationError {
    pub line: usize,
    pub message: String,
}

pub fn parse(script: &str) -> Result<Declaration, DeclarationError> {
    let mut decl = Declaration::default();
    for (i, line) in script.lines().enumerate() {
        let Some(text) = line.trim_start().strip_prefix("//!") else {
            if line.trim().is_empty() && decl.doc.is_empty() && decl.params.is_empty() {
                continue;
            }
            break;
        };
        let text = text.trim();
        let Some(param) = text.strip_prefix("@param") else {
            decl.doc.push(text.to_string());
            continue;
        };
        let error = |message: &str| DeclarationError {
            line: i + 1,
            message: message.to_string(),
        };
        let param = param.trim();
        let name_len = param
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(param.len());
        let name = &param[..name_len];
        if name.is_empty() || name.starts_with(|c: char| c.is_ascii_digit()) {
            return Err(error("`@param` needs a name: `//! @param width  doc`"));
        }
        if decl.params.iter().any(|p| p.name == name) {
            return Err(error(&format!("parameter `{name}` declared twice")));
        }
        let mut rest = param[name_len..].trim_start();
        let mut default = None;
        if let Some(after) = rest.strip_prefix('=') {
            let after = after.trim_start();
            let (value, tail) = split_default(after)
                .ok_or_else(|| error("a default is a number, a \"string\", true or false"))?;
            default = Some(value);
            rest = tail;
        } else if decl.params.last().is_some_and(|p| p.default.is_some()) {
            return Err(error(&format!(
                "`{name}` has no default but comes after one that has"
            )));
        }
        decl.params.push(Param {
            name: name.to_string(),
            default,
            doc: rest.trim().to_string(),
        });
    }
    Ok(decl)
}

fn split_default(text: &str) -> Option<(Default, &str)> {
    if let Some(body) = text.strip_prefix('"') {
        let end = body.find('"')?;
        return Some((Default::Str(body[..end].to_string()), &body[end + 1..]));
    }
    let end = text.find(char::is_whitespace).unwrap_or(text.len());
    let (word, rest) = text.split_at(end);
    let value = match word {
        "true" => Default::Bool(true),
        "false" => Default::Bool(false),
        _ => Default::Number(word.parse().ok()?),
    };
    Some((value, rest))
}

impl Declaration {
    pub fn summary(&self) -> &str {
        self.doc.first().map_or("", String::as_str)
    }

    /// `Pocket width height depth [stepdown=1]`
    pub fn signature(&self, name: &str) -> String {
        let mut s = name.to_string();
        for p in &self.params {
            s.push(' ');
            match &p.default {
                None => s.push_str(&p.name),
                Some(d) => s.push_str(&format!("[{}={}]", p.name, d)),
            }
        }
        s
    }
}

impl std::fmt::Display for Default {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Default::Number(n) => write!(f, "{n}"),
            Default::Str(s) => write!(f, "\"{s}\""),
            Default::Bool(b) => write!(f, "{b}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_doc_and_params() {
        let d = parse(
            "//! A pocket.\n//! More.\n//! @param width  the width\n//! @param step = 1.5 depth per pass\n//! @param kind = \"flat\"\nlet x = 1;\n//! ignored\n",
        )
        .unwrap();
        assert_eq!(d.doc, vec!["A pocket.", "More."]);
        assert_eq!(d.params.len(), 3);
        assert_eq!(d.params[1].default, Some(Default::Number(1.5)));
        assert_eq!(d.params[1].doc, "depth per pass");
        assert_eq!(d.params[2].default, Some(Default::Str("flat".into())));
        assert_eq!(
            d.signature("Pocket"),
            "Pocket width [step=1.5] [kind=\"flat\"]"
        );
    }

    #[test]
    fn rejects_required_after_optional() {
        let e = parse("//! @param a = 1\n//! @param b\n").unwrap_err();
        assert_eq!(e.line, 2);
    }
}
