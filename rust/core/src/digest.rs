//! Content digests of files: inputs recorded in a generation record, model checksums.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use sha2::{Digest, Sha256};

use crate::error::{CoreError, CoreResult};

const BUFFER_SIZE: usize = 1 << 20;

/// Returns the lower-case hex SHA-256 of the file at `path`, read in 1 MiB blocks.
pub fn sha256_file(path: &Path) -> CoreResult<String> {
    let mut file = File::open(path).map_err(|e| CoreError::io(path, e))?;
    if file
        .metadata()
        .map_err(|e| CoreError::io(path, e))?
        .is_dir()
    {
        return Err(CoreError::InvalidArgument(format!(
            "{}: is a folder, expected a file",
            path.display()
        )));
    }
    let mut hasher = Sha256::new();
    let mut buffer = vec![0u8; BUFFER_SIZE];
    loop {
        let read = file.read(&mut buffer).map_err(|e| CoreError::io(path, e))?;
        if read == 0 {
            break;
        }
        hasher.update(&buffer[..read]);
    }
    Ok(hex(&hasher.finalize()))
}

fn hex(bytes: &[u8]) -> String {
    const DIGITS: &[u8; 16] = b"0123456789abcdef";
    let mut out = String::with_capacity(bytes.len() * 2);
    for byte in bytes {
        out.push(char::from(DIGITS[usize::from(byte >> 4)]));
        out.push(char::from(DIGITS[usize::from(byte & 0x0f)]));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn sha256_of_known_content() -> CoreResult<()> {
        let mut file =
            tempfile::NamedTempFile::new().map_err(|e| CoreError::io(Path::new("tmp"), e))?;
        file.write_all(b"abc")
            .map_err(|e| CoreError::io(file.path(), e))?;
        assert_eq!(
            sha256_file(file.path())?,
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        Ok(())
    }

    #[test]
    fn sha256_of_missing_file_is_not_found() {
        let err = sha256_file(Path::new("/definitely/not/here.bin"));
        assert!(matches!(err, Err(CoreError::NotFound { .. })));
    }

    #[test]
    fn sha256_of_folder_is_invalid_argument() {
        let dir = std::env::temp_dir();
        assert!(matches!(
            sha256_file(&dir),
            Err(CoreError::InvalidArgument(_))
        ));
    }
}
