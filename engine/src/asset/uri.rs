//! URIs inside a glTF: `data:` URIs (base64, size-limited) and external files, which must be
//! relative paths inside the model's folder (no schemes, no absolute paths, no `..`).

use super::limits::MAX_DATA_URI_BYTES;

/// What a glTF `uri` refers to.
pub(crate) enum UriRef {
    /// Decoded bytes of a `data:` URI.
    Data(Vec<u8>),
    /// A safe relative path (percent-decoded, `/`-separated) next to the model.
    Relative(String),
}

/// Classifies and checks a URI; decodes `data:` URIs. Errors are plain problem strings.
pub(crate) fn resolve_uri(uri: &str) -> Result<UriRef, String> {
    if let Some(rest) = strip_prefix_ci(uri, "data:") {
        return decode_data_uri(rest).map(UriRef::Data);
    }
    relative_path(uri).map(UriRef::Relative)
}

fn strip_prefix_ci<'a>(s: &'a str, prefix: &str) -> Option<&'a str> {
    let head = s.get(..prefix.len())?;
    head.eq_ignore_ascii_case(prefix)
        .then(|| &s[prefix.len()..])
}

fn decode_data_uri(rest: &str) -> Result<Vec<u8>, String> {
    let comma = rest
        .find(',')
        .ok_or("malformed data URI: no ',' separator")?;
    let (meta, payload) = (&rest[..comma], &rest[comma + 1..]);
    if !meta.split(';').any(|p| p.eq_ignore_ascii_case("base64")) {
        return Err("unsupported data URI: only base64 payloads are supported".into());
    }
    if payload.len() > MAX_DATA_URI_BYTES {
        return Err(format!(
            "data URI too large: {} base64 bytes (limit {MAX_DATA_URI_BYTES})",
            payload.len()
        ));
    }
    base64_decode(payload.as_bytes())
}

fn b64_value(c: u8) -> Option<u32> {
    Some(match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' | b'-' => 62,
        b'/' | b'_' => 63,
        _ => return None,
    } as u32)
}

/// Strict base64 (standard or URL alphabet, optional `=` padding).
pub(crate) fn base64_decode(input: &[u8]) -> Result<Vec<u8>, String> {
    let trimmed = match input.iter().position(|&c| c == b'=') {
        Some(p) => {
            if input[p..].iter().any(|&c| c != b'=') || input.len() - p > 2 {
                return Err("malformed base64 in data URI: bad '=' padding".into());
            }
            &input[..p]
        }
        None => input,
    };
    if trimmed.len() % 4 == 1 {
        return Err("malformed base64 in data URI: truncated".into());
    }
    let mut out = Vec::with_capacity(trimmed.len() / 4 * 3 + 2);
    let mut acc = 0u32;
    let mut bits = 0u32;
    for (i, &c) in trimmed.iter().enumerate() {
        let v = b64_value(c).ok_or_else(|| {
            format!(
                "malformed base64 in data URI: invalid character {:?} at {i}",
                c as char
            )
        })?;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Ok(out)
}

fn percent_decode(s: &str) -> Result<String, String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = b
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("malformed percent-encoding in URI {s:?}"))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| format!("URI {s:?} is not UTF-8 after percent-decoding"))
}

/// Checks that an external URI is a plain relative path inside the model's folder.
pub(crate) fn relative_path(uri: &str) -> Result<String, String> {
    if uri.is_empty() {
        return Err("empty external URI".into());
    }
    let path = percent_decode(uri)?;
    let reject = |why: &str| Err(format!("external URI {uri:?} rejected: {why}"));
    if path.contains('\0') {
        return reject("contains NUL");
    }
    if path.starts_with('/') || path.starts_with('\\') {
        return reject("absolute path");
    }
    // `scheme:` (file:, http:, ...) and Windows drive letters (`C:`) both contain ':' before
    // the first separator; a ':' anywhere is never needed for a file next to the model.
    if path.contains(':') {
        return reject("absolute URI, scheme or drive letter (only relative paths are allowed)");
    }
    if path.split(['/', '\\']).any(|seg| seg == "..") {
        return reject("'..' escapes the model's folder");
    }
    if path.ends_with('/') || path.ends_with('\\') {
        return reject("names a folder");
    }
    Ok(path.replace('\\', "/"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_roundtrip_samples() {
        assert_eq!(base64_decode(b"").unwrap(), b"");
        assert_eq!(base64_decode(b"Zg==").unwrap(), b"f");
        assert_eq!(base64_decode(b"Zm8=").unwrap(), b"fo");
        assert_eq!(base64_decode(b"Zm9v").unwrap(), b"foo");
        assert_eq!(base64_decode(b"Zm9vYg").unwrap(), b"foob");
        assert!(base64_decode(b"Zm9v!").is_err());
        assert!(base64_decode(b"Z").is_err());
        assert!(base64_decode(b"Zg=a").is_err());
    }

    #[test]
    fn rejects_escaping_uris() {
        for bad in [
            "../x.bin",
            "a/../../x.bin",
            "/etc/passwd",
            "\\\\server\\share",
            "C:/x.bin",
            "c:x.bin",
            "file:///etc/passwd",
            "http://example.com/x.bin",
            "%2e%2e/x.bin",
            "",
        ] {
            assert!(relative_path(bad).is_err(), "{bad} accepted");
        }
        assert_eq!(relative_path("sub/a%20b.bin").unwrap(), "sub/a b.bin");
    }

    #[test]
    fn data_uri() {
        match resolve_uri("data:application/octet-stream;base64,AAEC").unwrap() {
            UriRef::Data(d) => assert_eq!(d, [0, 1, 2]),
            UriRef::Relative(_) => panic!(),
        }
        assert!(resolve_uri("data:application/octet-stream,abc").is_err());
        assert!(resolve_uri("data:;base64").is_err());
    }
}
