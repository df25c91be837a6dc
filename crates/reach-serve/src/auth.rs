//! The bearer token: created on the first start in `STATE/token` (mode 0600, 32 random bytes
//! as 64 hex digits) and required on every request (except `GET /openapi.json`) when the
//! service listens beyond loopback.

use std::io::{Read, Write};
use std::path::Path;

use crate::error::ServeError;

/// Reads the state directory's token, creating it on the first start.
///
/// # Errors
/// [`ServeError::Io`] when the file cannot be read or created, or the system has no
/// `/dev/urandom`.
pub fn token(dir: &Path) -> Result<String, ServeError> {
    let path = dir.join("token");
    if let Ok(text) = std::fs::read_to_string(&path) {
        let text = text.trim();
        if text.len() >= 32 {
            make_private(&path)?;
            return Ok(text.to_string());
        }
    }
    let mut bytes = [0u8; 32];
    std::fs::File::open("/dev/urandom")
        .and_then(|mut f| f.read_exact(&mut bytes))
        .map_err(|e| ServeError::io(Path::new("/dev/urandom"), &e))?;
    let token: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
    // A short or unreadable file is replaced, not rewritten: a new file gets mode 0600 (an
    // existing one would keep its mode).
    match std::fs::remove_file(&path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(ServeError::io(&path, &e)),
        _ => {}
    }
    let mut options = std::fs::OpenOptions::new();
    options.write(true).create_new(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.mode(0o600);
    }
    let mut file = options.open(&path).map_err(|e| ServeError::io(&path, &e))?;
    file.write_all(token.as_bytes()).and_then(|()| file.sync_all()).map_err(|e| ServeError::io(&path, &e))?;
    Ok(token)
}

/// Makes a file (mode 0600) or the state directory (0700) its owner's only, if it is not
/// already: no group or other permission bit is left.
///
/// # Errors
/// [`ServeError::Io`] when the mode cannot be read or set.
pub fn make_private(path: &Path) -> Result<(), ServeError> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let meta = std::fs::metadata(path).map_err(|e| ServeError::io(path, &e))?;
        let mode = if meta.is_dir() { 0o700 } else { 0o600 };
        if meta.permissions().mode() & 0o777 != mode {
            std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode))
                .map_err(|e| ServeError::io(path, &e))?;
        }
    }
    #[cfg(not(unix))]
    let _ = path;
    Ok(())
}

/// Whether `given` equals `expected`, in time independent of where they differ.
#[must_use]
pub fn same_token(given: &str, expected: &str) -> bool {
    given.len() == expected.len() && given.bytes().zip(expected.bytes()).fold(0u8, |acc, (a, b)| acc | (a ^ b)) == 0
}
