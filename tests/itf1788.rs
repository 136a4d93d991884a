//! IEEE 1788 conformance: the ITF1788 test vectors run against `Interval<f64>`.
//!
//! The [ITF1788] test files (`*.itl`, the Interval Test Language) are read at
//! test time from `../shared/itf1788` beside the repository, or from the
//! folder named by the `BOUNDTRACE_ITF1788_DIR` environment variable. They are
//! data, never copied into the repository. Each statement such as
//!
//! ```text
//! testcase minimal_add_test {
//!     add [-1.0, 2.0] [3.0, 4.0] = [2.0, 6.0];
//! }
//! ```
//!
//! is parsed, the operation is evaluated with
//! [`Interval<f64>`](boundtrace::ia_core::Interval), and the result judged:
//!
//! - **interval results** (`add`, `sqrt`, `pown`, `sin`, ...): the expected
//!   interval (the tightest enclosure) must be a subset of ours. Equal results
//!   count as *tight*; wider ones are *wider*, with the distance of each
//!   differing bound in float steps (ulps) in a histogram. A non-empty result
//!   where `EMPTY` is expected is sound but counted separately.
//! - **`inf`, `sup`, `mag`, `mig`, `isEmpty`, `isEntire`, `subset`,
//!   `isMember`**: exactly equal (`-0 == +0`; NaN matches NaN).
//! - **`mid`**: inside the interval, finite (NaN only where the vector says
//!   NaN); equal to the vector or not (both are valid midpoints).
//! - **`rad`, `wid`**: at least the expected value (an upper bound is sound).
//!
//! Decorated test cases (`*_dec*` names, `_com`/`_dac`/`_def`/`_trv`/`_ill`
//! suffixes, `[nai]`) and operations `Interval` does not offer (`fma`, `tan`,
//! `mulRev`, ...) are skipped and counted. `pow` runs only with a non-empty
//! point exponent `[p, p]` (what [`Interval::pow`] takes).
//!
//! # Literals
//!
//! Hexadecimal literals (`0x1.FFFFFFFFFFFFFp1023`, `0X3.8F5C28F5C28F4P+0`) are
//! converted exactly; a literal that is not a binary64 number is a parse
//! error. Decimal literals are read in two ways:
//!
//! 1. **nearest** (the main run): the binary64 number nearest to the
//!    literal, as the ITF1788 generators emit it (a C++ `double` literal)
//!    and as the vectors were computed: e.g. `pow [0.1,0.5] [0.0,1.0]` expects
//!    the lower bound `0X1.999999999999AP-4`, which is the nearest double to
//!    0.1 and lies *above* the real 0.1.
//! 2. **exact decimal** (a second run of the interval-valued statements
//!    whose interval literals hold a decimal that is not a binary64 number):
//!    such a lower bound is stepped one float down and an upper bound one
//!    float up, in the operands *and* in the expected result, so the
//!    intervals enclose the exact decimal values. Containment must hold here
//!    too; these runs are counted separately.
//!
//! A line that cannot be parsed is reported. For an operation `Interval`
//! implements it fails the test, so no vector is silently dropped.
//!
//! # Running
//!
//! ```text
//! cargo test --test itf1788 -- --nocapture
//! ```
//!
//! prints the report (per operation: run, tight, wider, violations,
//! skipped, and the ulp histogram), which is also written to
//! `$CARGO_TARGET_TMPDIR/itf1788-report.txt`. Without the vectors the test
//! passes with a message, except with `CI=true`, where they are required.
//!
//! [ITF1788]: https://github.com/oheim/ITF1788

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use boundtrace::ia_core::Interval;

type I = Interval<f64>;

/// Where the vectors are when `BOUNDTRACE_ITF1788_DIR` is not set.
const DEFAULT_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/itf1788");

/// The ITL operations evaluated here; all others are skipped and counted.
const IMPLEMENTED: &[&str] = &[
    "pos",
    "neg",
    "add",
    "sub",
    "mul",
    "div",
    "recip",
    "sqr",
    "sqrt",
    "pown",
    "pow",
    "exp",
    "log",
    "sin",
    "cos",
    "abs",
    "min",
    "max",
    "intersection",
    "convexHull",
    "inf",
    "sup",
    "mid",
    "rad",
    "wid",
    "mag",
    "mig",
    "isEmpty",
    "isEntire",
    "subset",
    "isMember",
];

// ---------------------------------------------------------------------------
// Floats: exact stepping, ulp distance, hexadecimal output.
// ---------------------------------------------------------------------------

/// The least float above `x` (written here, independent of the code under test).
fn step_up(x: f64) -> f64 {
    if x.is_nan() || x == f64::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1);
    }
    let b = x.to_bits();
    f64::from_bits(if x > 0.0 { b + 1 } else { b - 1 })
}

/// The greatest float below `x`.
fn step_down(x: f64) -> f64 {
    -step_up(-x)
}

/// Position of `x` on the line of floats (`-0` and `+0` share 0).
fn float_index(x: f64) -> i128 {
    let b = x.to_bits();
    let magnitude = i128::from(b & !(1u64 << 63));
    if b >> 63 == 1 { -magnitude } else { magnitude }
}

/// Number of float steps between `a` and `b`.
fn ulps_between(a: f64, b: f64) -> u128 {
    (float_index(a) - float_index(b)).unsigned_abs()
}

/// `x` as an exact C99-style hexadecimal float (`-0x1.999999999999ap-4`).
fn hex(x: f64) -> String {
    if x.is_nan() {
        return "NaN".to_owned();
    }
    if x.is_infinite() {
        return if x > 0.0 { "+infinity" } else { "-infinity" }.to_owned();
    }
    let bits = x.to_bits();
    let sign = if bits >> 63 == 1 { "-" } else { "" };
    let biased = ((bits >> 52) & 0x7ff) as i64;
    let fraction = bits & ((1u64 << 52) - 1);
    if biased == 0 && fraction == 0 {
        return format!("{sign}0x0p+0");
    }
    let (lead, exp) = if biased == 0 {
        (0, -1022)
    } else {
        (1, biased - 1023)
    };
    let digits = format!("{fraction:013x}");
    let digits = digits.trim_end_matches('0');
    let dot = if digits.is_empty() { "" } else { "." };
    format!("{sign}0x{lead}{dot}{digits}p{exp:+}")
}

/// An interval for messages: `[empty]` or `[lo, hi]` in hex floats.
fn show(x: I) -> String {
    if x.is_empty() && x.lo() == f64::INFINITY && x.hi() == f64::NEG_INFINITY {
        "[empty]".to_owned()
    } else {
        format!("[{}, {}]", hex(x.lo()), hex(x.hi()))
    }
}

// ---------------------------------------------------------------------------
// Number literals.
// ---------------------------------------------------------------------------

/// A parsed number literal.
#[derive(Clone, Debug)]
struct Num {
    /// The literal as written.
    raw: String,
    /// Its value: exact for hex literals and infinities, the nearest binary64
    /// number for decimal literals.
    value: f64,
    /// Whether `value` equals the literal exactly.
    exact: bool,
}

/// Parses an ITL number: hex or decimal float, integer, `±infinity`, `NaN`.
fn parse_number(raw: &str) -> Result<Num, String> {
    let (negative, body) = match raw.as_bytes().first() {
        Some(b'-') => (true, &raw[1..]),
        Some(b'+') => (false, &raw[1..]),
        _ => (false, raw),
    };
    let signed = |v: f64| if negative { -v } else { v };
    let lower = body.to_ascii_lowercase();
    let (value, exact) = if lower == "infinity" || lower == "inf" {
        (signed(f64::INFINITY), true)
    } else if lower == "nan" {
        (f64::NAN, true)
    } else if lower.starts_with("0x") {
        (parse_hex(negative, &body[2..])?, true)
    } else {
        parse_decimal(negative, body)?
    };
    Ok(Num {
        raw: raw.to_owned(),
        value,
        exact,
    })
}

/// `m · 2^e` (with sign) as an f64, or an error when that is no binary64 number.
fn exact_f64(negative: bool, mut m: u128, mut e: i64) -> Result<f64, String> {
    let sign_bit = if negative { 1u64 << 63 } else { 0 };
    if m == 0 {
        return Ok(f64::from_bits(sign_bit));
    }
    let zeros = m.trailing_zeros();
    m >>= zeros;
    e += i64::from(zeros);
    let len = i64::from(128 - m.leading_zeros());
    if len > 53 {
        return Err(format!("not a binary64 number ({len} significant bits)"));
    }
    // Exponent of the leading bit.
    let top = e + len - 1;
    let bits = if top > 1023 {
        return Err("overflows binary64".to_owned());
    } else if top >= -1022 {
        let significand = (m as u64) << (53 - len);
        (((top + 1023) as u64) << 52) | (significand & ((1u64 << 52) - 1))
    } else {
        // Subnormal: m · 2^e = f · 2^−1074 with f < 2^52.
        if e < -1074 {
            return Err("below the binary64 subnormal range".to_owned());
        }
        (m as u64) << (e + 1074)
    };
    Ok(f64::from_bits(bits | sign_bit))
}

/// The digits after `0x` of a hex float (`1.FFFp-3`) or hex integer (`1F`).
fn parse_hex(negative: bool, s: &str) -> Result<f64, String> {
    let (mantissa, exp) = match s.find(['p', 'P']) {
        Some(i) => {
            let exp_text = &s[i + 1..];
            let exp: i64 = exp_text
                .parse()
                .map_err(|_| format!("bad binary exponent `{exp_text}`"))?;
            if exp.abs() > 100_000 {
                return Err("binary exponent out of range".to_owned());
            }
            (&s[..i], exp)
        }
        None if !s.contains('.') => (s, 0),
        None => return Err("hex float without binary exponent".to_owned()),
    };
    let (int_part, frac_part) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    if int_part.is_empty() && frac_part.is_empty() {
        return Err("hex literal without digits".to_owned());
    }
    let mut m: u128 = 0;
    for c in int_part.chars().chain(frac_part.chars()) {
        let d = c
            .to_digit(16)
            .ok_or_else(|| format!("bad hex digit `{c}`"))?;
        if m >> 120 != 0 {
            return Err("too many hex digits".to_owned());
        }
        m = (m << 4) | u128::from(d);
    }
    exact_f64(negative, m, exp - 4 * frac_part.len() as i64)
}

/// A decimal literal (`12.4`, `1.e-3`, `5`): the nearest f64, and whether it
/// is exact.
fn parse_decimal(negative: bool, s: &str) -> Result<(f64, bool), String> {
    let (mantissa, exp_text) = match s.find(['e', 'E']) {
        Some(i) => (&s[..i], Some(&s[i + 1..])),
        None => (s, None),
    };
    let (int_part, frac_part) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let all_digits = |t: &str| t.bytes().all(|b| b.is_ascii_digit());
    if (int_part.is_empty() && frac_part.is_empty())
        || !all_digits(int_part)
        || !all_digits(frac_part)
    {
        return Err(format!("not a number literal: `{s}`"));
    }
    let exp: i64 = match exp_text {
        Some(t) => {
            let digits = t.strip_prefix(['+', '-']).unwrap_or(t);
            if digits.is_empty() || !all_digits(digits) || digits.len() > 9 {
                return Err(format!("bad decimal exponent in `{s}`"));
            }
            t.parse()
                .map_err(|_| format!("bad decimal exponent in `{s}`"))?
        }
        None => 0,
    };
    // Rust's float parsing is correctly rounded (round to nearest, ties to even).
    let magnitude: f64 = s
        .parse()
        .map_err(|e| format!("not a number literal: `{s}` ({e})"))?;
    if magnitude.is_infinite() {
        return Err(format!("decimal literal `{s}` overflows binary64"));
    }
    let literal = normalize_decimal(
        &format!("{int_part}{frac_part}"),
        exp - frac_part.len() as i64,
    );
    // The exact decimal expansion of the f64 (Rust's fixed-precision
    // formatting is exact; 800 digits cover every binary64 number).
    let expansion = format!("{magnitude:.800e}");
    let (digits, e10) = expansion
        .split_once('e')
        .ok_or_else(|| "unexpected float formatting".to_owned())?;
    let e10: i64 = e10
        .parse()
        .map_err(|_| "unexpected float formatting".to_owned())?;
    let digits = digits.replace('.', "");
    let value = normalize_decimal(&digits, e10 - (digits.len() as i64 - 1));
    let v = if negative { -magnitude } else { magnitude };
    Ok((v, literal == value))
}

/// `digits · 10^exp` in a canonical form: no leading or trailing zeros
/// (zero is `("", 0)`).
fn normalize_decimal(digits: &str, exp: i64) -> (String, i64) {
    let trimmed = digits.trim_start_matches('0');
    let significant = trimmed.trim_end_matches('0');
    if significant.is_empty() {
        return (String::new(), 0);
    }
    let dropped = (trimmed.len() - significant.len()) as i64;
    (significant.to_owned(), exp + dropped)
}

// ---------------------------------------------------------------------------
// ITL lexer and parser.
// ---------------------------------------------------------------------------

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    /// Identifiers, numbers, `-infinity`, `_com`, `b-textToInterval`, ...
    Word(String),
    /// A quoted string (`"[1, 2]"`), without the quotes.
    Str(String),
    /// One of `{ } ; = [ ] ,`.
    Punct(char),
}

#[derive(Clone, Debug)]
struct Token {
    tok: Tok,
    line: usize,
    start: usize,
    end: usize,
}

/// Splits ITL source into tokens, dropping `/* */`, `//` and `#* *#` comments.
fn lex(src: &str) -> Result<Vec<Token>, (usize, String)> {
    let bytes = src.as_bytes();
    let mut tokens = Vec::new();
    let (mut i, mut line) = (0usize, 1usize);
    let is_word = |b: u8| b.is_ascii_alphanumeric() || b"_.+-".contains(&b);
    while i < bytes.len() {
        let b = bytes[i];
        let rest = &src[i..];
        if b == b'\n' {
            line += 1;
            i += 1;
        } else if b.is_ascii_whitespace() {
            i += 1;
        } else if rest.starts_with("/*") || rest.starts_with("#*") {
            let close = if b == b'/' { "*/" } else { "*#" };
            let end = rest[2..]
                .find(close)
                .ok_or((line, "unterminated block comment".to_owned()))?;
            let comment = &rest[..end + 4];
            line += comment.matches('\n').count();
            i += comment.len();
        } else if rest.starts_with("//") {
            i += rest.find('\n').unwrap_or(rest.len());
        } else if b == b'"' {
            let mut j = i + 1;
            while j < bytes.len() && bytes[j] != b'"' {
                if bytes[j] == b'\n' {
                    return Err((line, "newline in string".to_owned()));
                }
                j += if bytes[j] == b'\\' { 2 } else { 1 };
            }
            if j >= bytes.len() {
                return Err((line, "unterminated string".to_owned()));
            }
            tokens.push(Token {
                tok: Tok::Str(src[i + 1..j].to_owned()),
                line,
                start: i,
                end: j + 1,
            });
            i = j + 1;
        } else if b"{};=[],".contains(&b) {
            tokens.push(Token {
                tok: Tok::Punct(char::from(b)),
                line,
                start: i,
                end: i + 1,
            });
            i += 1;
        } else if is_word(b) {
            let mut j = i;
            while j < bytes.len() && is_word(bytes[j]) {
                j += 1;
            }
            tokens.push(Token {
                tok: Tok::Word(src[i..j].to_owned()),
                line,
                start: i,
                end: j,
            });
            i = j;
        } else {
            let c = rest.chars().next().unwrap_or('?');
            return Err((line, format!("unexpected character `{c}`")));
        }
    }
    Ok(tokens)
}

/// An interval literal's contents.
#[derive(Clone, Debug)]
enum IntervalLit {
    Empty,
    Entire,
    Nai,
    Bounds(Num, Num),
}

/// A value in a statement.
#[derive(Clone, Debug)]
enum Value {
    Interval {
        lit: IntervalLit,
        /// The decoration suffix (`com`, `dac`, `def`, `trv`, `ill`), if any.
        dec: Option<String>,
    },
    Number(Num),
    Bool(bool),
    Str(String),
    /// A bare word such as an `overlap` state (`before`, `meets`, ...).
    Ident(String),
    Array(Vec<Value>),
}

impl Value {
    /// The value in ITL-like notation, for messages.
    fn describe(&self) -> String {
        match self {
            Value::Interval { lit, dec } => {
                let body = match lit {
                    IntervalLit::Empty => "[empty]".to_owned(),
                    IntervalLit::Entire => "[entire]".to_owned(),
                    IntervalLit::Nai => "[nai]".to_owned(),
                    IntervalLit::Bounds(lo, hi) => format!("[{}, {}]", lo.raw, hi.raw),
                };
                match dec {
                    Some(d) => format!("interval {body}_{d}"),
                    None => format!("interval {body}"),
                }
            }
            Value::Number(n) => format!("number {}", n.raw),
            Value::Bool(b) => format!("boolean {b}"),
            Value::Str(s) => format!("string \"{s}\""),
            Value::Ident(w) => format!("name `{w}`"),
            Value::Array(items) => format!("array of {} values", items.len()),
        }
    }
}

/// A statement `op ARGS = RESULTS [signal NAME];`.
#[derive(Clone, Debug)]
struct Parsed {
    args: Vec<Value>,
    results: Vec<Value>,
}

/// One statement of a test file, parsed or not.
#[derive(Clone, Debug)]
struct Stmt {
    file: String,
    testcase: String,
    line: usize,
    /// The statement as written (comments removed, on one line).
    text: String,
    op: String,
    body: Result<Parsed, String>,
}

/// A test file's statements, and the structural error that ended reading it
/// early, if any.
fn parse_file(file: &str, src: &str) -> (Vec<Stmt>, Option<(usize, String)>) {
    let tokens = match lex(src) {
        Ok(t) => t,
        Err(e) => return (Vec::new(), Some(e)),
    };
    let mut stmts = Vec::new();
    let mut pos = 0;
    while pos < tokens.len() {
        let line = tokens[pos].line;
        if tokens[pos].tok != Tok::Word("testcase".to_owned()) {
            return (stmts, Some((line, "expected `testcase`".to_owned())));
        }
        let name = match tokens.get(pos + 1).map(|t| &t.tok) {
            Some(Tok::Word(n)) => n.clone(),
            _ => return (stmts, Some((line, "expected a testcase name".to_owned()))),
        };
        if tokens.get(pos + 2).map(|t| &t.tok) != Some(&Tok::Punct('{')) {
            return (
                stmts,
                Some((line, "expected `{` after the testcase name".to_owned())),
            );
        }
        pos += 3;
        // Statements up to the closing `}` (braces of array values nest).
        let mut current: Vec<Token> = Vec::new();
        let mut depth = 0usize;
        loop {
            let Some(t) = tokens.get(pos) else {
                return (
                    stmts,
                    Some((line, format!("testcase `{name}` is not closed"))),
                );
            };
            pos += 1;
            match t.tok {
                Tok::Punct('}') if depth == 0 => {
                    if !current.is_empty() {
                        let mut s = make_stmt(file, &name, src, &current);
                        s.body = Err("missing `;` before `}`".to_owned());
                        stmts.push(s);
                    }
                    break;
                }
                Tok::Punct(';') if depth == 0 => {
                    if !current.is_empty() {
                        stmts.push(make_stmt(file, &name, src, &current));
                        current.clear();
                    }
                }
                _ => {
                    if t.tok == Tok::Punct('{') {
                        depth += 1;
                    } else if t.tok == Tok::Punct('}') {
                        depth -= 1;
                    }
                    current.push(t.clone());
                }
            }
        }
    }
    (stmts, None)
}

/// A statement from its tokens (without the `;`).
fn make_stmt(file: &str, testcase: &str, src: &str, toks: &[Token]) -> Stmt {
    let first = &toks[0];
    let last = &toks[toks.len() - 1];
    let text = src[first.start..last.end]
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    let op = match &first.tok {
        Tok::Word(w) => w.clone(),
        _ => String::new(),
    };
    let body = if op.is_empty() {
        Err("a statement must start with an operation name".to_owned())
    } else {
        parse_stmt(&toks[1..])
    };
    Stmt {
        file: file.to_owned(),
        testcase: testcase.to_owned(),
        line: first.line,
        text: format!("{text};"),
        op,
        body,
    }
}

fn parse_stmt(toks: &[Token]) -> Result<Parsed, String> {
    let mut pos = 0;
    let mut args = Vec::new();
    while toks.get(pos).map(|t| &t.tok) != Some(&Tok::Punct('=')) {
        if pos >= toks.len() {
            return Err("missing `=`".to_owned());
        }
        args.push(parse_value(toks, &mut pos)?);
    }
    pos += 1;
    let mut results = Vec::new();
    while pos < toks.len() {
        if let Tok::Word(w) = &toks[pos].tok {
            if w == "signal" {
                match toks.get(pos + 1).map(|t| &t.tok) {
                    Some(Tok::Word(_)) if pos + 2 == toks.len() => break,
                    _ => return Err("`signal` must be followed by one name".to_owned()),
                }
            }
        }
        results.push(parse_value(toks, &mut pos)?);
    }
    if results.is_empty() {
        return Err("no result after `=`".to_owned());
    }
    Ok(Parsed { args, results })
}

fn parse_value(toks: &[Token], pos: &mut usize) -> Result<Value, String> {
    let tok = toks
        .get(*pos)
        .map(|t| t.tok.clone())
        .ok_or("unexpected end of statement")?;
    *pos += 1;
    match tok {
        Tok::Punct('[') => parse_interval(toks, pos),
        Tok::Punct('{') => {
            let mut items = Vec::new();
            loop {
                match toks.get(*pos).map(|t| &t.tok) {
                    Some(Tok::Punct('}')) => {
                        *pos += 1;
                        return Ok(Value::Array(items));
                    }
                    Some(Tok::Punct(',')) if !items.is_empty() => *pos += 1,
                    Some(_) if items.is_empty() => {}
                    _ => return Err("bad array literal".to_owned()),
                }
                items.push(parse_value(toks, pos)?);
            }
        }
        Tok::Str(s) => Ok(Value::Str(s)),
        Tok::Word(w) => {
            let unsigned = w.trim_start_matches(['+', '-']);
            let lower = unsigned.to_ascii_lowercase();
            if w == "true" || w == "false" {
                Ok(Value::Bool(w == "true"))
            } else if unsigned.starts_with(|c: char| c.is_ascii_digit() || c == '.')
                || lower == "infinity"
                || lower == "inf"
                || lower == "nan"
            {
                Ok(Value::Number(parse_number(&w)?))
            } else if w.starts_with(|c: char| c.is_ascii_alphabetic()) {
                Ok(Value::Ident(w))
            } else {
                Err(format!("unexpected `{w}`"))
            }
        }
        Tok::Punct(c) => Err(format!("unexpected `{c}`")),
    }
}

/// The rest of an interval literal after `[`, and its decoration suffix.
fn parse_interval(toks: &[Token], pos: &mut usize) -> Result<Value, String> {
    let word = |p: usize| match toks.get(p).map(|t| &t.tok) {
        Some(Tok::Word(w)) => Some(w.clone()),
        _ => None,
    };
    let punct = |p: usize, c: char| toks.get(p).map(|t| &t.tok) == Some(&Tok::Punct(c));
    let first = word(*pos).ok_or("expected a bound or `empty`/`entire`/`nai` after `[`")?;
    let lit = match first.as_str() {
        "empty" | "entire" | "nai" if punct(*pos + 1, ']') => {
            *pos += 2;
            match first.as_str() {
                "empty" => IntervalLit::Empty,
                "entire" => IntervalLit::Entire,
                _ => IntervalLit::Nai,
            }
        }
        _ => {
            let lo = parse_number(&first)?;
            if punct(*pos + 1, ']') {
                // `[x]`: the point interval.
                *pos += 2;
                IntervalLit::Bounds(lo.clone(), lo)
            } else if punct(*pos + 1, ',') && punct(*pos + 3, ']') {
                let hi = word(*pos + 2).ok_or("expected an upper bound")?;
                let hi = parse_number(&hi)?;
                *pos += 4;
                IntervalLit::Bounds(lo, hi)
            } else {
                return Err("malformed interval literal".to_owned());
            }
        }
    };
    let dec = match word(*pos) {
        Some(w) if w.starts_with('_') => {
            *pos += 1;
            let d = w[1..].to_owned();
            if !["com", "dac", "def", "trv", "ill"].contains(&d.as_str()) {
                return Err(format!("unknown decoration `_{d}`"));
            }
            Some(d)
        }
        _ => None,
    };
    Ok(Value::Interval { lit, dec })
}

// ---------------------------------------------------------------------------
// Evaluation.
// ---------------------------------------------------------------------------

/// How decimal literals of interval bounds are read (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    /// The nearest binary64 number (how the vectors were generated).
    Nearest,
    /// An enclosure of the exact decimal: an inexact lower bound stepped one
    /// float down, an inexact upper bound one float up.
    ExactDecimal,
}

/// A result: ours, or the one a vector expects.
#[derive(Clone, Copy, Debug)]
enum Val {
    Iv(I),
    Num(f64),
    Bool(bool),
}

impl Val {
    fn show(self) -> String {
        match self {
            Val::Iv(x) => show(x),
            Val::Num(x) => hex(x),
            Val::Bool(b) => b.to_string(),
        }
    }
}

/// A statement evaluated: our result, the expected one, and the first
/// interval operand (which `mid` must lie in).
struct Case {
    got: Val,
    want: Val,
    operand: I,
}

enum Prep {
    Run(Case),
    Skip(&'static str),
}

/// Whether any value carries a decoration or is `[nai]`.
fn is_decorated(values: &[Value]) -> bool {
    values.iter().any(|v| match v {
        Value::Interval { lit, dec } => dec.is_some() || matches!(lit, IntervalLit::Nai),
        Value::Array(items) => is_decorated(items),
        _ => false,
    })
}

/// Whether an interval literal has a decimal bound that is not a binary64 number.
fn has_inexact_bound(values: &[Value]) -> bool {
    values.iter().any(|v| match v {
        Value::Interval {
            lit: IntervalLit::Bounds(lo, hi),
            ..
        } => !lo.exact || !hi.exact,
        _ => false,
    })
}

/// The interval a literal denotes in `mode`.
fn to_interval(v: &Value, mode: Mode) -> Result<I, String> {
    let Value::Interval { lit, .. } = v else {
        return Err(format!("expected an interval, found {}", v.describe()));
    };
    match lit {
        IntervalLit::Empty => Ok(I::EMPTY),
        IntervalLit::Entire => Ok(I::ENTIRE),
        IntervalLit::Nai => Err("[nai] is not a bare interval".to_owned()),
        IntervalLit::Bounds(lo, hi) => {
            let (mut a, mut b) = (lo.value, hi.value);
            if mode == Mode::ExactDecimal {
                if !lo.exact {
                    a = step_down(a);
                }
                if !hi.exact {
                    b = step_up(b);
                }
            }
            if a.is_nan() || b.is_nan() || a > b || a == f64::INFINITY || b == f64::NEG_INFINITY {
                return Err(format!("invalid interval [{}, {}]", lo.raw, hi.raw));
            }
            Ok(I::new(a, b))
        }
    }
}

fn to_number(v: &Value) -> Result<f64, String> {
    match v {
        Value::Number(n) => Ok(n.value),
        _ => Err(format!("expected a number, found {}", v.describe())),
    }
}

fn to_bool(v: &Value) -> Result<bool, String> {
    match v {
        Value::Bool(b) => Ok(*b),
        _ => Err(format!("expected a boolean, found {}", v.describe())),
    }
}

fn to_i32(v: &Value) -> Result<i32, String> {
    match v {
        Value::Number(n) => n
            .raw
            .parse()
            .map_err(|_| format!("expected an integer exponent, found `{}`", n.raw)),
        _ => Err(format!("expected an integer, found {}", v.describe())),
    }
}

/// Whether `op` returns an interval.
fn interval_valued(op: &str) -> bool {
    !matches!(
        op,
        "inf"
            | "sup"
            | "mid"
            | "rad"
            | "wid"
            | "mag"
            | "mig"
            | "isEmpty"
            | "isEntire"
            | "subset"
            | "isMember"
    )
}

/// Evaluates an implemented operation; `Err` means the statement does not
/// have the shape the operation needs (a parse error).
fn evaluate(op: &str, p: &Parsed, mode: Mode) -> Result<Prep, String> {
    let arity = match op {
        "add" | "sub" | "mul" | "div" | "min" | "max" | "intersection" | "convexHull" | "pown"
        | "pow" | "subset" | "isMember" => 2,
        _ => 1,
    };
    if p.args.len() != arity || p.results.len() != 1 {
        return Err(format!(
            "`{op}` takes {arity} operand(s) and 1 result, found {} and {}",
            p.args.len(),
            p.results.len()
        ));
    }
    let iv = |k: usize| to_interval(&p.args[k], mode);
    // `isMember` has the interval second; all others first.
    let operand = if op == "isMember" { iv(1)? } else { iv(0)? };
    let want_iv = || to_interval(&p.results[0], mode).map(Val::Iv);
    let want_num = || to_number(&p.results[0]).map(Val::Num);
    let want_bool = || to_bool(&p.results[0]).map(Val::Bool);
    let x = operand;
    let (got, want) = match op {
        "pos" => (Val::Iv(x), want_iv()?),
        "neg" => (Val::Iv(-x), want_iv()?),
        "add" => (Val::Iv(x + iv(1)?), want_iv()?),
        "sub" => (Val::Iv(x - iv(1)?), want_iv()?),
        "mul" => (Val::Iv(x * iv(1)?), want_iv()?),
        "div" => (Val::Iv(x / iv(1)?), want_iv()?),
        "recip" => (Val::Iv(x.recip()), want_iv()?),
        "sqr" => (Val::Iv(x.sqr()), want_iv()?),
        "sqrt" => (Val::Iv(x.sqrt()), want_iv()?),
        "pown" => (Val::Iv(x.powi(to_i32(&p.args[1])?)), want_iv()?),
        "pow" => {
            let e = iv(1)?;
            let want = want_iv()?;
            if e.is_empty() || e.lo() != e.hi() {
                return Ok(Prep::Skip("pow with a non-point exponent"));
            }
            (Val::Iv(x.pow(e.lo())), want)
        }
        "exp" => (Val::Iv(x.exp()), want_iv()?),
        "log" => (Val::Iv(x.ln()), want_iv()?),
        "sin" => (Val::Iv(x.sin()), want_iv()?),
        "cos" => (Val::Iv(x.cos()), want_iv()?),
        "abs" => (Val::Iv(x.abs()), want_iv()?),
        "min" => (Val::Iv(x.min(iv(1)?)), want_iv()?),
        "max" => (Val::Iv(x.max(iv(1)?)), want_iv()?),
        "intersection" => (Val::Iv(x.intersection(iv(1)?)), want_iv()?),
        "convexHull" => (Val::Iv(x.hull(iv(1)?)), want_iv()?),
        "inf" => (Val::Num(x.lo()), want_num()?),
        "sup" => (Val::Num(x.hi()), want_num()?),
        "mid" => (Val::Num(x.mid()), want_num()?),
        "rad" => (Val::Num(x.rad()), want_num()?),
        "wid" => (Val::Num(x.width()), want_num()?),
        "mag" => (Val::Num(x.mag()), want_num()?),
        "mig" => (Val::Num(x.mig()), want_num()?),
        "isEmpty" => (Val::Bool(x.is_empty()), want_bool()?),
        "isEntire" => (Val::Bool(x.is_entire()), want_bool()?),
        "subset" => (Val::Bool(x.subset(iv(1)?)), want_bool()?),
        "isMember" => (Val::Bool(x.contains(to_number(&p.args[0])?)), want_bool()?),
        _ => return Err(format!("`{op}` is not implemented by the harness")),
    };
    Ok(Prep::Run(Case { got, want, operand }))
}

// ---------------------------------------------------------------------------
// Judging and statistics.
// ---------------------------------------------------------------------------

/// Labels of the ulp histogram buckets.
const BUCKETS: [&str; 6] = ["1", "2", "3-4", "5-16", ">16", "unb"];

/// Histogram bucket of a bound `got` that is wider than `want`.
fn bucket(want: f64, got: f64) -> usize {
    if got.is_infinite() && want.is_finite() {
        return 5;
    }
    match ulps_between(want, got) {
        0 | 1 => 0,
        2 => 1,
        3..=4 => 2,
        5..=16 => 3,
        _ => 4,
    }
}

/// How far a wider result is from the expected one: the most float steps
/// of a bound (`None`: unbounded, or non-empty where `EMPTY` is expected).
fn wider_distance(got: Val, want: Val) -> Option<u128> {
    let dist = |want: f64, got: f64| {
        if got.is_infinite() && want.is_finite() {
            None
        } else {
            Some(ulps_between(want, got))
        }
    };
    match (got, want) {
        (Val::Iv(g), Val::Iv(w)) if !w.is_empty() => {
            Some(dist(w.lo(), g.lo())?.max(dist(w.hi(), g.hi())?))
        }
        (Val::Num(g), Val::Num(w)) => dist(w, g),
        _ => None,
    }
}

/// How many of the widest results the report lists.
const WIDEST_LISTED: usize = 25;

enum Verdict {
    Tight,
    /// Sound but not tightest: the histogram buckets of the differing bounds,
    /// and whether we returned a non-empty interval where `EMPTY` is expected.
    Wider(Vec<usize>, bool),
    Violation(String),
}

/// Checks the representation invariant documented by `Interval`.
fn well_formed(x: I) -> Result<(), String> {
    let (a, b) = (x.lo(), x.hi());
    if a.is_nan() || b.is_nan() {
        return Err("NaN bound".to_owned());
    }
    if a > b {
        if a == f64::INFINITY && b == f64::NEG_INFINITY {
            return Ok(());
        }
        return Err("lo > hi but not the canonical EMPTY [+inf, -inf]".to_owned());
    }
    if a == f64::INFINITY || b == f64::NEG_INFINITY {
        return Err("[+inf, +inf] or [-inf, -inf] is no interval".to_owned());
    }
    Ok(())
}

fn judge(op: &str, case: &Case) -> Verdict {
    match (case.got, case.want) {
        (Val::Iv(got), Val::Iv(want)) => {
            if let Err(e) = well_formed(got) {
                return Verdict::Violation(format!("malformed result: {e}"));
            }
            if want.is_empty() {
                return if got.is_empty() {
                    Verdict::Tight
                } else {
                    Verdict::Wider(Vec::new(), true)
                };
            }
            if got.is_empty() || got.lo() > want.lo() || got.hi() < want.hi() {
                return Verdict::Violation("expected interval not contained in result".to_owned());
            }
            let mut buckets = Vec::new();
            if got.lo() != want.lo() {
                buckets.push(bucket(want.lo(), got.lo()));
            }
            if got.hi() != want.hi() {
                buckets.push(bucket(want.hi(), got.hi()));
            }
            if buckets.is_empty() {
                Verdict::Tight
            } else {
                Verdict::Wider(buckets, false)
            }
        }
        (Val::Num(got), Val::Num(want)) => match op {
            "mid" => {
                if want.is_nan() || got.is_nan() {
                    return if want.is_nan() && got.is_nan() {
                        Verdict::Tight
                    } else {
                        Verdict::Violation("NaN mismatch".to_owned())
                    };
                }
                let x = case.operand;
                if !got.is_finite() || got < x.lo() || got > x.hi() {
                    Verdict::Violation("midpoint not a finite point of the interval".to_owned())
                } else if got == want {
                    Verdict::Tight
                } else {
                    // Another valid midpoint: counted as wider, no ulp bucket.
                    Verdict::Wider(Vec::new(), false)
                }
            }
            "rad" | "wid" => {
                if want.is_nan() || got.is_nan() {
                    return if want.is_nan() && got.is_nan() {
                        Verdict::Tight
                    } else {
                        Verdict::Violation("NaN mismatch".to_owned())
                    };
                }
                if got < want {
                    Verdict::Violation("below the exact value (unsound)".to_owned())
                } else if got == want {
                    Verdict::Tight
                } else {
                    Verdict::Wider(vec![bucket(want, got)], false)
                }
            }
            _ => {
                if got == want || (got.is_nan() && want.is_nan()) {
                    Verdict::Tight
                } else {
                    Verdict::Violation("not equal".to_owned())
                }
            }
        },
        (Val::Bool(got), Val::Bool(want)) => {
            if got == want {
                Verdict::Tight
            } else {
                Verdict::Violation("not equal".to_owned())
            }
        }
        _ => Verdict::Violation("result kinds differ (harness bug)".to_owned()),
    }
}

#[derive(Clone, Default)]
struct OpStats {
    run: u64,
    tight: u64,
    wider: u64,
    violations: u64,
    skipped: u64,
    /// Non-empty results where `EMPTY` is expected.
    nonempty_for_empty: u64,
    /// Differing bounds per ulp bucket (see [`BUCKETS`]).
    hist: [u64; 6],
    /// Statements re-run with exact-decimal literals.
    exact_runs: u64,
    /// ... of which the expected result was widened.
    exact_widened_want: u64,
    exact_violations: u64,
    exact_skipped: u64,
}

impl OpStats {
    fn add(&mut self, o: &OpStats) {
        self.run += o.run;
        self.tight += o.tight;
        self.wider += o.wider;
        self.violations += o.violations;
        self.skipped += o.skipped;
        self.nonempty_for_empty += o.nonempty_for_empty;
        for (h, x) in self.hist.iter_mut().zip(o.hist) {
            *h += x;
        }
        self.exact_runs += o.exact_runs;
        self.exact_widened_want += o.exact_widened_want;
        self.exact_violations += o.exact_violations;
        self.exact_skipped += o.exact_skipped;
    }
}

struct Problem {
    stmt: Stmt,
    message: String,
}

impl Problem {
    fn describe(&self) -> String {
        format!(
            "{}:{} [{}] {}\n        {}",
            self.stmt.file, self.stmt.line, self.stmt.testcase, self.stmt.text, self.message
        )
    }
}

#[derive(Default)]
struct Run {
    files: Vec<(String, usize)>,
    stats: BTreeMap<String, OpStats>,
    /// Statements of operations not implemented, per operation.
    unsupported: BTreeMap<String, u64>,
    /// Skipped statements of implemented operations, per (op, reason).
    skip_reasons: BTreeMap<(String, &'static str), u64>,
    violations: Vec<Problem>,
    /// Wider results with their distance (see [`wider_distance`]).
    wider: Vec<(Option<u128>, Problem)>,
    /// Parse errors in statements of implemented operations (fatal).
    fatal_parse_errors: Vec<Problem>,
    /// Parse errors in statements of other operations (reported only).
    other_parse_errors: Vec<Problem>,
    /// Files that could not be read or parsed to the end (fatal).
    file_errors: Vec<String>,
}

impl Run {
    fn statement(&mut self, stmt: Stmt) {
        let op = stmt.op.clone();
        if !IMPLEMENTED.contains(&op.as_str()) {
            *self.unsupported.entry(op).or_default() += 1;
            if let Err(e) = &stmt.body {
                let message = format!("parse error: {e}");
                self.other_parse_errors.push(Problem { stmt, message });
            }
            return;
        }
        let parsed = match &stmt.body {
            Ok(p) => p.clone(),
            Err(e) => {
                let message = format!("parse error: {e}");
                self.fatal_parse_errors.push(Problem { stmt, message });
                return;
            }
        };
        let decorated = stmt.testcase.contains("_dec")
            || is_decorated(&parsed.args)
            || is_decorated(&parsed.results);
        if decorated {
            self.stats.entry(op.clone()).or_default().skipped += 1;
            *self.skip_reasons.entry((op, "decorated")).or_default() += 1;
            return;
        }
        for mode in [Mode::Nearest, Mode::ExactDecimal] {
            if mode == Mode::ExactDecimal
                && !(interval_valued(&op)
                    && (has_inexact_bound(&parsed.args) || has_inexact_bound(&parsed.results)))
            {
                continue;
            }
            let prep = match evaluate(&op, &parsed, mode) {
                Ok(p) => p,
                Err(e) => {
                    let message = format!("parse error: {e}");
                    self.fatal_parse_errors.push(Problem {
                        stmt: stmt.clone(),
                        message,
                    });
                    return;
                }
            };
            let s = self.stats.entry(op.clone()).or_default();
            let case = match prep {
                Prep::Run(case) => case,
                Prep::Skip(reason) => {
                    if mode == Mode::Nearest {
                        s.skipped += 1;
                        *self.skip_reasons.entry((op.clone(), reason)).or_default() += 1;
                    } else {
                        s.exact_skipped += 1;
                    }
                    continue;
                }
            };
            let verdict = judge(&op, &case);
            if mode == Mode::ExactDecimal {
                s.exact_runs += 1;
                if has_inexact_bound(&parsed.results) {
                    s.exact_widened_want += 1;
                }
                if let Verdict::Violation(why) = verdict {
                    s.exact_violations += 1;
                    let message = format!(
                        "[exact-decimal reading] {why}\n        expected {}\n        got      {}",
                        case.want.show(),
                        case.got.show()
                    );
                    self.violations.push(Problem {
                        stmt: stmt.clone(),
                        message,
                    });
                }
                continue;
            }
            s.run += 1;
            match verdict {
                Verdict::Tight => s.tight += 1,
                Verdict::Wider(buckets, nonempty) => {
                    let dist = wider_distance(case.got, case.want);
                    let message = format!(
                        "{}\n        expected {}\n        got      {}",
                        match dist {
                            Some(d) => format!("{d} ulp(s) wider"),
                            None if nonempty => "non-empty where EMPTY is expected".to_owned(),
                            None => "unbounded where the tightest bound is finite".to_owned(),
                        },
                        case.want.show(),
                        case.got.show()
                    );
                    self.wider.push((
                        dist,
                        Problem {
                            stmt: stmt.clone(),
                            message,
                        },
                    ));
                    s.wider += 1;
                    s.nonempty_for_empty += u64::from(nonempty);
                    for b in buckets {
                        s.hist[b] += 1;
                    }
                }
                Verdict::Violation(why) => {
                    s.violations += 1;
                    let message = format!(
                        "{why}\n        expected {}\n        got      {}",
                        case.want.show(),
                        case.got.show()
                    );
                    self.violations.push(Problem {
                        stmt: stmt.clone(),
                        message,
                    });
                }
            }
        }
    }

    fn totals(&self) -> OpStats {
        let mut t = OpStats::default();
        for s in self.stats.values() {
            t.add(s);
        }
        t
    }

    fn failed(&self) -> bool {
        !self.violations.is_empty()
            || !self.fatal_parse_errors.is_empty()
            || !self.file_errors.is_empty()
            || self.totals().run == 0
    }

    fn report(&self, dir: &Path) -> String {
        let mut r = String::new();
        let total = self.totals();
        let unsupported: u64 = self.unsupported.values().sum();
        let _ = writeln!(
            r,
            "ITF1788 conformance of boundtrace::ia_core::Interval<f64>"
        );
        let _ = writeln!(r, "vectors: {}", dir.display());
        for (f, n) in &self.files {
            let _ = writeln!(r, "  {f}: {n} statements");
        }
        let _ = writeln!(r);
        let _ = writeln!(
            r,
            "Per operation (wider: sound, not tightest; the ulp columns count differing \
             bounds of wider results; unb: infinite where the tightest bound is finite; \
             !empty: non-empty where EMPTY is expected; for mid, wider = another valid midpoint)"
        );
        let header = format!(
            "{:<13}{:>6}{:>7}{:>7}{:>6}{:>6} |{:>6}{:>6}{:>6}{:>6}{:>6}{:>6}{:>8}",
            "op",
            "run",
            "tight",
            "wider",
            "viol",
            "skip",
            BUCKETS[0],
            BUCKETS[1],
            BUCKETS[2],
            BUCKETS[3],
            BUCKETS[4],
            BUCKETS[5],
            "!empty"
        );
        let _ = writeln!(r, "{header}");
        let _ = writeln!(r, "{}", "-".repeat(header.len()));
        let row = |name: &str, s: &OpStats| {
            format!(
                "{:<13}{:>6}{:>7}{:>7}{:>6}{:>6} |{:>6}{:>6}{:>6}{:>6}{:>6}{:>6}{:>8}",
                name,
                s.run,
                s.tight,
                s.wider,
                s.violations,
                s.skipped,
                s.hist[0],
                s.hist[1],
                s.hist[2],
                s.hist[3],
                s.hist[4],
                s.hist[5],
                s.nonempty_for_empty
            )
        };
        for op in IMPLEMENTED {
            let s = self.stats.get(*op).cloned().unwrap_or_default();
            let _ = writeln!(r, "{}", row(op, &s));
        }
        let _ = writeln!(r, "{}", "-".repeat(header.len()));
        let _ = writeln!(r, "{}", row("total", &total));
        let _ = writeln!(r);
        let _ = writeln!(
            r,
            "Totals: {} run, {} tight, {} wider, {} violations; {} skipped in implemented \
             operations; {} statements of {} operations not implemented",
            total.run,
            total.tight,
            total.wider,
            total.violations,
            total.skipped,
            unsupported,
            self.unsupported.len()
        );
        let _ = writeln!(r);
        let _ = writeln!(r, "Skipped in implemented operations:");
        for ((op, reason), n) in &self.skip_reasons {
            let _ = writeln!(r, "  {op:<13}{n:>6}  {reason}");
        }
        let _ = writeln!(r);
        let _ = writeln!(
            r,
            "Operations not implemented by Interval (statements skipped):"
        );
        let mut by_count: Vec<_> = self.unsupported.iter().collect();
        by_count.sort_by(|a, b| b.1.cmp(a.1).then(a.0.cmp(b.0)));
        for chunk in by_count.chunks(4) {
            let line: Vec<String> = chunk
                .iter()
                .map(|(op, n)| format!("{op:<20}{n:>5}"))
                .collect();
            let _ = writeln!(r, "  {}", line.join("   "));
        }
        let _ = writeln!(r);
        let _ = writeln!(
            r,
            "Exact-decimal reading (interval literals with a decimal bound that is not a \
             binary64 number, widened one float outward in operands and expected result):"
        );
        let _ = writeln!(
            r,
            "  {:<13}{:>6}{:>16}{:>8}{:>8}",
            "op", "runs", "want widened", "viol", "skip"
        );
        for (op, s) in &self.stats {
            if s.exact_runs + s.exact_skipped > 0 {
                let _ = writeln!(
                    r,
                    "  {:<13}{:>6}{:>16}{:>8}{:>8}",
                    op, s.exact_runs, s.exact_widened_want, s.exact_violations, s.exact_skipped
                );
            }
        }
        let _ = writeln!(
            r,
            "  {:<13}{:>6}{:>16}{:>8}{:>8}",
            "total",
            total.exact_runs,
            total.exact_widened_want,
            total.exact_violations,
            total.exact_skipped
        );
        let _ = writeln!(r);
        let _ = writeln!(
            r,
            "Parse errors: {} in implemented operations (fatal), {} in other operations",
            self.fatal_parse_errors.len(),
            self.other_parse_errors.len()
        );
        for p in self
            .fatal_parse_errors
            .iter()
            .chain(&self.other_parse_errors)
        {
            let _ = writeln!(r, "  {}", p.describe());
        }
        for e in &self.file_errors {
            let _ = writeln!(r, "  FILE: {e}");
        }
        let _ = writeln!(r);
        let mut widest: Vec<&(Option<u128>, Problem)> = self.wider.iter().collect();
        // Unbounded / non-empty-for-EMPTY first, then by distance; stable.
        widest.sort_by_key(|(d, _)| std::cmp::Reverse(d.unwrap_or(u128::MAX)));
        let _ = writeln!(
            r,
            "Widest results ({} of {} wider, by the farther bound, in float steps):",
            widest.len().min(WIDEST_LISTED),
            widest.len()
        );
        for (_, p) in widest.iter().take(WIDEST_LISTED) {
            let _ = writeln!(r, "  {}", p.describe());
        }
        let _ = writeln!(r);
        let _ = writeln!(r, "Violations: {}", self.violations.len());
        for v in &self.violations {
            let _ = writeln!(r, "  {}", v.describe());
        }
        let _ = writeln!(r);
        let _ = writeln!(
            r,
            "Result: {}",
            if self.failed() { "FAILED" } else { "passed" }
        );
        r
    }
}

/// The folder of the vectors, or `None` (with the reason) when absent.
fn vector_dir() -> Result<PathBuf, String> {
    let dir = std::env::var_os("BOUNDTRACE_ITF1788_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(DEFAULT_DIR));
    let has_itl = std::fs::read_dir(&dir)
        .map(|entries| {
            entries
                .flatten()
                .any(|e| e.path().extension().is_some_and(|x| x == "itl"))
        })
        .unwrap_or(false);
    if has_itl {
        Ok(dir)
    } else {
        Err(format!(
            "no ITF1788 vectors (*.itl) in {} (set BOUNDTRACE_ITF1788_DIR to their folder)",
            dir.display()
        ))
    }
}

fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v.eq_ignore_ascii_case("true") || v == "1")
}

#[test]
fn itf1788_vectors() {
    let dir = match vector_dir() {
        Ok(d) => d,
        Err(why) => {
            assert!(
                !in_ci(),
                "{why}: the ITF1788 vectors are required in CI (CI=true)"
            );
            println!("SKIPPED the ITF1788 conformance test: {why}");
            return;
        }
    };
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|entries| {
            entries
                .flatten()
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == "itl"))
                .collect()
        })
        .unwrap_or_default();
    paths.sort();
    let mut run = Run::default();
    for path in &paths {
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let src = match std::fs::read_to_string(path) {
            Ok(s) => s,
            Err(e) => {
                run.file_errors.push(format!("{name}: cannot read: {e}"));
                continue;
            }
        };
        let (stmts, error) = parse_file(&name, &src);
        run.files.push((name.clone(), stmts.len()));
        if let Some((line, e)) = error {
            run.file_errors.push(format!(
                "{name}:{line}: {e} (the rest of the file is not read)"
            ));
        }
        for stmt in stmts {
            run.statement(stmt);
        }
    }

    let report = run.report(&dir);
    println!("{report}");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("itf1788-report.txt");
    match std::fs::create_dir_all(env!("CARGO_TARGET_TMPDIR"))
        .and_then(|()| std::fs::write(&out, &report))
    {
        Ok(()) => println!("report written to {}", out.display()),
        Err(e) => println!("could not write the report to {}: {e}", out.display()),
    }

    let mut failures = String::new();
    for e in &run.file_errors {
        let _ = writeln!(failures, "file error: {e}");
    }
    for p in &run.fatal_parse_errors {
        let _ = writeln!(failures, "{}", p.describe());
    }
    for v in &run.violations {
        let _ = writeln!(failures, "{}", v.describe());
    }
    if run.totals().run == 0 {
        let _ = writeln!(failures, "no statement of an implemented operation was run");
    }
    assert!(
        !run.failed(),
        "ITF1788: {} violation(s), {} parse error(s) in implemented operations, {} file \
         error(s):\n{failures}",
        run.violations.len(),
        run.fatal_parse_errors.len(),
        run.file_errors.len()
    );
}

/// The literal parser itself, on the forms the files use.
#[test]
fn literal_parser() {
    let v = |s: &str| parse_number(s).map(|n| (n.value, n.exact));
    assert_eq!(v("0x1.FFFFFFFFFFFFFp1023"), Ok((f64::MAX, true)));
    assert_eq!(v("-0x1.FFFFFFFFFFFFFp1023"), Ok((-f64::MAX, true)));
    assert_eq!(v("0X0.0000000000001P-1022"), Ok((f64::from_bits(1), true)));
    assert_eq!(v("0X1P-1074"), Ok((f64::from_bits(1), true)));
    assert_eq!(v("0x1p-1022"), Ok((f64::MIN_POSITIVE, true)));
    assert_eq!(v("-0x1p+0"), Ok((-1.0, true)));
    assert_eq!(v("0X1.999999999999AP-4"), Ok((0.1, true)));
    assert_eq!(
        v("0XA.AAAAAAAAAAAB0P-4"),
        Ok((f64::from_bits(0x3FE5_5555_5555_5556), true))
    );
    assert_eq!(
        v("0X3.8F5C28F5C28F4P+0"),
        Ok((f64::from_bits(0x400C_7AE1_47AE_147A), true))
    );
    assert!(v("0x1.00000000000001p0").is_err()); // 57 bits
    assert!(v("0x1p1024").is_err());
    assert!(v("0x1p-1075").is_err());
    assert_eq!(v("1.0"), Ok((1.0, true)));
    assert_eq!(v("-7451.145"), Ok((-7451.145, false)));
    assert_eq!(v("0.1"), Ok((0.1, false)));
    assert_eq!(v("2.5"), Ok((2.5, true)));
    assert_eq!(v("1e3"), Ok((1000.0, true)));
    assert_eq!(v("1.e-3"), Ok((0.001, false)));
    assert_eq!(v("0.000001"), Ok((1e-6, false)));
    assert_eq!(
        v("-0.0").map(|(x, e)| (x.to_bits(), e)),
        Ok(((-0.0f64).to_bits(), true))
    );
    assert_eq!(v("+infinity"), Ok((f64::INFINITY, true)));
    assert_eq!(v("-infinity"), Ok((f64::NEG_INFINITY, true)));
    assert!(v("NaN").is_ok_and(|(x, _)| x.is_nan()));
    assert!(v("1.0E+400").is_err());
    assert!(v("1.2.3").is_err());
    // 2^-1074 written out in decimal is exact.
    let tiny = format!("{:.1074}", f64::from_bits(1));
    assert_eq!(v(&tiny), Ok((f64::from_bits(1), true)));
    assert_eq!(hex(0.1), "0x1.999999999999ap-4");
    assert_eq!(hex(-f64::from_bits(1)), "-0x0.0000000000001p-1022");
    assert_eq!(hex(1.0), "0x1p+0");
    assert_eq!(ulps_between(-0.0, f64::from_bits(2)), 2);
    assert_eq!(step_down(0.0), -f64::from_bits(1));
    assert_eq!(step_up(-f64::from_bits(1)), 0.0);
}
