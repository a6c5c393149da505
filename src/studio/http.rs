//! The studio's HTTP/1.1, bounded before anything is allocated: a request's head is read
//! up to [`HEAD_BYTES`], a body only once its announced length is known to fit
//! [`MAX_UPLOAD`] (a larger one is answered 413 without being read), a chunked body only
//! when it ends with its last chunk (one cut short is dropped, never handled), and the
//! connections open at once are capped by the server ([`MAX_CONNECTIONS`]).
//!
//! Written here rather than taken from a crate: tiny_http, which served the studio before,
//! reserved a buffer of the announced `Content-Length` while it drained an unread body (a
//! request announcing 10¹² bytes aborted the process wherever that allocation failed) and
//! gave every connection a thread with no cap. The studio speaks to one page on loopback;
//! what it needs of HTTP is this file.

use std::io::{self, BufRead, Read, Write};

pub use crate::limits::{HEAD_BYTES, MAX_CONNECTIONS, MAX_HEADERS, MAX_UPLOAD};

/// One request as read off the connection.
#[derive(Debug)]
pub struct HttpRequest {
    /// GET, POST, …
    pub method: String,
    /// The request target: path and query.
    pub target: String,
    /// Header names (as sent) and values, in order.
    pub headers: Vec<(String, String)>,
    /// The body, whole.
    pub body: Vec<u8>,
    /// Whether the client keeps the connection for another request.
    pub keep_alive: bool,
}

impl HttpRequest {
    /// The value of header `name` if the request carries it exactly once; a repeated
    /// header reads as the empty string (so a repeated `Host` or `Origin` is foreign).
    pub fn header(&self, name: &str) -> Option<String> {
        let mut values = self
            .headers
            .iter()
            .filter(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, v)| v.clone());
        let first = values.next();
        match values.next() {
            Some(_) => Some(String::new()),
            None => first,
        }
    }
}

/// What reading a request came to.
#[derive(Debug)]
pub enum Read1 {
    /// A whole request.
    Request(HttpRequest),
    /// The connection ended (or idled past its timeout) between requests, or in the
    /// middle of one: nothing to answer, nothing handled.
    Ended,
    /// A request that is refused before it is handled: answer with this status and
    /// message, then close the connection (its remaining bytes are never read).
    Refused(u16, &'static str),
}

/// Reads one request from `reader`. `continue_to` receives `100 Continue` when the client
/// asked for it and the announced body fits.
pub fn read_request(reader: &mut impl BufRead, continue_to: &mut impl Write) -> Read1 {
    let head = match read_head(reader) {
        Ok(Some(head)) => head,
        Ok(None) => return Read1::Ended,
        Err(refusal) => return refusal,
    };
    let mut request = match parse_head(&head) {
        Ok(request) => request,
        Err(refusal) => return refusal,
    };
    let body = match body_framing(&request) {
        Ok(framing) => framing,
        Err(refusal) => return refusal,
    };
    if body != Framing::None
        && request
            .header("Expect")
            .is_some_and(|e| e.eq_ignore_ascii_case("100-continue"))
    {
        // Only now, with the length known to fit, is the client asked for its body.
        if continue_to
            .write_all(b"HTTP/1.1 100 Continue\r\n\r\n")
            .and_then(|_| continue_to.flush())
            .is_err()
        {
            return Read1::Ended;
        }
    }
    let read = match body {
        Framing::None => Ok(Vec::new()),
        Framing::Length(n) => read_exactly(reader, n),
        Framing::Chunked => read_chunked(reader),
    };
    match read {
        Ok(bytes) => {
            request.body = bytes;
            Read1::Request(request)
        }
        Err(BodyError::Incomplete) => Read1::Ended,
        Err(BodyError::TooLarge) => Read1::Refused(413, "the body is larger than the studio takes"),
        Err(BodyError::Malformed) => Read1::Refused(400, "a malformed chunked body"),
    }
}

/// The request a head's lines describe (its body still unread), or why it is refused.
fn parse_head(head: &[String]) -> Result<HttpRequest, Read1> {
    let mut lines = head.iter();
    let Some(request_line) = lines.next() else {
        return Err(Read1::Ended);
    };
    let mut words = request_line.split(' ');
    let (Some(method), Some(target), Some(version), None) =
        (words.next(), words.next(), words.next(), words.next())
    else {
        return Err(Read1::Refused(400, "a malformed request line"));
    };
    let http10 = match version {
        "HTTP/1.1" => false,
        "HTTP/1.0" => true,
        _ => return Err(Read1::Refused(505, "only HTTP/1.1 and 1.0 are spoken here")),
    };
    if method.is_empty() || !method.bytes().all(|b| b.is_ascii_uppercase()) || target.is_empty() {
        return Err(Read1::Refused(400, "a malformed request line"));
    }
    let mut headers = Vec::new();
    for line in lines {
        let Some((name, value)) = line.split_once(':') else {
            return Err(Read1::Refused(400, "a header line without a colon"));
        };
        if name.is_empty() || name.bytes().any(|b| b.is_ascii_whitespace()) {
            return Err(Read1::Refused(400, "a malformed header name"));
        }
        if headers.len() == MAX_HEADERS {
            return Err(Read1::Refused(431, "too many header lines"));
        }
        headers.push((name.to_string(), value.trim().to_string()));
    }
    let mut request = HttpRequest {
        method: method.to_string(),
        target: target.to_string(),
        headers,
        body: Vec::new(),
        keep_alive: false,
    };
    let connection = request
        .header("Connection")
        .unwrap_or_default()
        .to_ascii_lowercase();
    request.keep_alive = if http10 {
        connection.contains("keep-alive")
    } else {
        !connection.contains("close")
    };
    Ok(request)
}

/// How the body is delimited.
#[derive(Debug, PartialEq)]
enum Framing {
    None,
    Length(usize),
    Chunked,
}

/// The body's framing from the headers, refusing what is ambiguous (both a length and a
/// transfer coding, two different lengths: the shapes request smuggling takes) or past
/// [`MAX_UPLOAD`].
fn body_framing(request: &HttpRequest) -> Result<Framing, Read1> {
    let lengths: Vec<&str> = request
        .headers
        .iter()
        .filter(|(n, _)| n.eq_ignore_ascii_case("Content-Length"))
        .flat_map(|(_, v)| v.split(','))
        .map(str::trim)
        .collect();
    let coding = request.header("Transfer-Encoding");
    match (lengths.first(), coding) {
        (None, None) => Ok(Framing::None),
        (Some(_), Some(_)) => Err(Read1::Refused(
            400,
            "both Content-Length and Transfer-Encoding",
        )),
        (None, Some(coding)) if coding.eq_ignore_ascii_case("chunked") => Ok(Framing::Chunked),
        (None, Some(_)) => Err(Read1::Refused(501, "a transfer coding other than chunked")),
        (Some(first), None) => {
            if lengths.iter().any(|l| l != first) {
                return Err(Read1::Refused(400, "two different Content-Length values"));
            }
            // Digits only: no sign, no space, and at most what a u64 holds.
            if first.is_empty() || first.len() > 19 || !first.bytes().all(|b| b.is_ascii_digit()) {
                return Err(Read1::Refused(400, "a malformed Content-Length"));
            }
            let n: u64 = first
                .parse()
                .map_err(|_| Read1::Refused(400, "a malformed Content-Length"))?;
            if n > MAX_UPLOAD as u64 {
                return Err(Read1::Refused(
                    413,
                    "the body is larger than the studio takes",
                ));
            }
            Ok(if n == 0 {
                Framing::None
            } else {
                Framing::Length(n as usize)
            })
        }
    }
}

/// The head's lines (request line first), without their line ends; `None` when the
/// connection ended before a request began.
fn read_head(reader: &mut impl BufRead) -> Result<Option<Vec<String>>, Read1> {
    let mut lines = Vec::new();
    let mut read = 0;
    loop {
        let mut line = Vec::new();
        let budget = (HEAD_BYTES - read) as u64;
        match reader.take(budget).read_until(b'\n', &mut line) {
            Ok(0) if lines.is_empty() && line.is_empty() => return Ok(None),
            Ok(_) => {}
            Err(_) => return Ok(None),
        }
        read += line.len();
        if line.last() != Some(&b'\n') {
            if read >= HEAD_BYTES {
                return Err(Read1::Refused(431, "the request's head is too large"));
            }
            // The connection ended mid-head.
            return Ok(None);
        }
        line.pop();
        if line.last() == Some(&b'\r') {
            line.pop();
        }
        if line.is_empty() {
            if lines.is_empty() {
                // Blank lines before a request line are tolerated (RFC 9112 §2.2).
                continue;
            }
            return Ok(Some(lines));
        }
        let Ok(text) = String::from_utf8(line) else {
            return Err(Read1::Refused(400, "a head that is not text"));
        };
        lines.push(text);
    }
}

#[derive(Debug)]
enum BodyError {
    /// The connection ended before the body did.
    Incomplete,
    /// Past [`MAX_UPLOAD`].
    TooLarge,
    /// Chunk framing that does not parse.
    Malformed,
}

/// `n` bytes, grown as they arrive (never reserved up front beyond 1 MiB).
fn read_exactly(reader: &mut impl BufRead, n: usize) -> Result<Vec<u8>, BodyError> {
    let mut body = Vec::with_capacity(n.min(1 << 20));
    match reader.take(n as u64).read_to_end(&mut body) {
        Ok(got) if got == n => Ok(body),
        _ => Err(BodyError::Incomplete),
    }
}

/// A chunked body, whole: every chunk's size checked against what is left of
/// [`MAX_UPLOAD`] before it is read, and the body complete only at its zero-size chunk
/// and the blank line after the trailers.
fn read_chunked(reader: &mut impl BufRead) -> Result<Vec<u8>, BodyError> {
    let mut body = Vec::new();
    loop {
        let line = read_short_line(reader)?;
        let size_text = line.split(';').next().unwrap_or("").trim();
        if size_text.is_empty()
            || size_text.len() > 16
            || !size_text.bytes().all(|b| b.is_ascii_hexdigit())
        {
            return Err(BodyError::Malformed);
        }
        let size = u64::from_str_radix(size_text, 16).map_err(|_| BodyError::Malformed)?;
        if size == 0 {
            // Trailers, up to the blank line that ends the body.
            loop {
                if read_short_line(reader)?.is_empty() {
                    return Ok(body);
                }
            }
        }
        if body.len() as u64 + size > MAX_UPLOAD as u64 {
            return Err(BodyError::TooLarge);
        }
        let chunk = read_exactly(reader, size as usize)?;
        body.extend_from_slice(&chunk);
        if !read_short_line(reader)?.is_empty() {
            return Err(BodyError::Malformed);
        }
    }
}

/// A chunk-size or trailer line of at most 1 KiB.
fn read_short_line(reader: &mut impl BufRead) -> Result<String, BodyError> {
    let mut line = Vec::new();
    reader
        .take(1024)
        .read_until(b'\n', &mut line)
        .map_err(|_| BodyError::Incomplete)?;
    if line.last() != Some(&b'\n') {
        return Err(if line.len() >= 1024 {
            BodyError::Malformed
        } else {
            BodyError::Incomplete
        });
    }
    line.pop();
    if line.last() == Some(&b'\r') {
        line.pop();
    }
    String::from_utf8(line).map_err(|_| BodyError::Malformed)
}

/// One response.
pub struct HttpResponse<'a> {
    /// The status code.
    pub status: u16,
    /// Header names and values; a value with a control character is left out.
    pub headers: Vec<(&'a str, String)>,
    /// The body (not sent for HEAD; its length still is).
    pub body: &'a [u8],
}

/// Writes `response` with its `Content-Length` and `Connection` headers.
pub fn write_response(
    out: &mut impl Write,
    response: &HttpResponse,
    head_only: bool,
    keep_alive: bool,
) -> io::Result<()> {
    let mut head = format!(
        "HTTP/1.1 {} {}\r\n",
        response.status,
        reason(response.status)
    );
    for (name, value) in &response.headers {
        if value
            .bytes()
            .all(|b| b == b'\t' || (b' '..=b'~').contains(&b))
        {
            head.push_str(&format!("{name}: {value}\r\n"));
        }
    }
    head.push_str(&format!(
        "Content-Length: {}\r\nConnection: {}\r\n\r\n",
        response.body.len(),
        if keep_alive { "keep-alive" } else { "close" }
    ));
    out.write_all(head.as_bytes())?;
    if !head_only {
        out.write_all(response.body)?;
    }
    out.flush()
}

/// The reason phrase of the statuses the studio sends.
fn reason(status: u16) -> &'static str {
    match status {
        100 => "Continue",
        200 => "OK",
        204 => "No Content",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        409 => "Conflict",
        413 => "Content Too Large",
        415 => "Unsupported Media Type",
        422 => "Unprocessable Content",
        429 => "Too Many Requests",
        431 => "Request Header Fields Too Large",
        500 => "Internal Server Error",
        501 => "Not Implemented",
        503 => "Service Unavailable",
        505 => "HTTP Version Not Supported",
        _ => "",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::BufReader;

    fn read(raw: &[u8]) -> (Read1, Vec<u8>) {
        let mut continued = Vec::new();
        let r = read_request(&mut BufReader::new(raw), &mut continued);
        (r, continued)
    }

    #[test]
    fn a_request_with_a_body_is_read_whole() {
        let (r, _) = read(b"POST /api/x?a=1 HTTP/1.1\r\nHost: h\r\nContent-Length: 5\r\n\r\nhello");
        let Read1::Request(r) = r else {
            panic!("{r:?}")
        };
        assert_eq!(
            (r.method.as_str(), r.target.as_str()),
            ("POST", "/api/x?a=1")
        );
        assert_eq!(r.body, b"hello");
        assert_eq!(r.header("host").as_deref(), Some("h"));
        assert!(r.keep_alive);
    }

    #[test]
    fn a_huge_announced_body_is_refused_unread() {
        let (r, continued) = read(
            b"GET / HTTP/1.1\r\nContent-Length: 1000000000000\r\nExpect: 100-continue\r\n\r\n",
        );
        assert!(matches!(r, Read1::Refused(413, _)), "{r:?}");
        assert!(
            continued.is_empty(),
            "no 100 Continue for a body that is refused"
        );
        let (r, _) = read(b"GET / HTTP/1.1\r\nContent-Length: 99999999999999999999999\r\n\r\n");
        assert!(matches!(r, Read1::Refused(400, _)), "{r:?}");
    }

    #[test]
    fn a_body_cut_short_is_never_handled() {
        let (r, _) = read(b"POST / HTTP/1.1\r\nContent-Length: 10\r\n\r\nabc");
        assert!(matches!(r, Read1::Ended), "{r:?}");
        // A chunk that claims 4 GiB and ends: too large for the studio, never handled.
        let (r, _) = read(b"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\nFFFFFFFF\r\nabc");
        assert!(matches!(r, Read1::Refused(413, _)), "{r:?}");
        // Chunks that fit but stop before the last chunk.
        let (r, _) = read(b"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n3\r\nabc\r\n");
        assert!(matches!(r, Read1::Ended), "{r:?}");
    }

    #[test]
    fn a_chunked_body_is_read_to_its_last_chunk() {
        let (r, _) = read(
            b"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n3;x=y\r\nabc\r\n2\r\nde\r\n0\r\nT: 1\r\n\r\n",
        );
        let Read1::Request(r) = r else {
            panic!("{r:?}")
        };
        assert_eq!(r.body, b"abcde");
    }

    #[test]
    fn ambiguous_framing_and_oversized_heads_are_refused() {
        let (r, _) =
            read(b"POST / HTTP/1.1\r\nContent-Length: 3\r\nTransfer-Encoding: chunked\r\n\r\nabc");
        assert!(matches!(r, Read1::Refused(400, _)), "{r:?}");
        let (r, _) = read(b"POST / HTTP/1.1\r\nContent-Length: 3\r\nContent-Length: 4\r\n\r\nabcd");
        assert!(matches!(r, Read1::Refused(400, _)), "{r:?}");
        let mut big = b"GET / HTTP/1.1\r\nX: ".to_vec();
        big.extend(std::iter::repeat_n(b'a', HEAD_BYTES));
        let (r, _) = read(&big);
        assert!(matches!(r, Read1::Refused(431, _)), "{r:?}");
        let mut many = b"GET / HTTP/1.1\r\n".to_vec();
        for i in 0..=MAX_HEADERS {
            many.extend(format!("X{i}: 1\r\n").bytes());
        }
        many.extend(b"\r\n");
        let (r, _) = read(&many);
        assert!(matches!(r, Read1::Refused(431, _)), "{r:?}");
    }

    #[test]
    fn expect_continue_is_answered_once_the_length_fits() {
        let (r, continued) =
            read(b"POST / HTTP/1.1\r\nContent-Length: 2\r\nExpect: 100-continue\r\n\r\nok");
        assert!(matches!(r, Read1::Request(_)), "{r:?}");
        assert_eq!(continued, b"HTTP/1.1 100 Continue\r\n\r\n");
    }

    #[test]
    fn http10_closes_unless_asked_and_a_repeated_header_reads_empty() {
        let (r, _) = read(b"GET / HTTP/1.0\r\nHost: a\r\nHost: b\r\n\r\n");
        let Read1::Request(r) = r else {
            panic!("{r:?}")
        };
        assert!(!r.keep_alive);
        assert_eq!(r.header("Host").as_deref(), Some(""));
    }

    #[test]
    fn a_response_leaves_out_header_values_with_control_characters() {
        let mut out = Vec::new();
        let response = HttpResponse {
            status: 200,
            headers: vec![("A", "ok".into()), ("B", "x\r\nInjected: 1".into())],
            body: b"body",
        };
        write_response(&mut out, &response, false, false).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.starts_with("HTTP/1.1 200 OK\r\nA: ok\r\n"), "{text}");
        assert!(!text.contains("Injected"), "{text}");
        assert!(text.ends_with("Content-Length: 4\r\nConnection: close\r\n\r\nbody"));
    }
}
