//! Reading the files a scene names (the scene itself, meshes, terrain grids): regular
//! files only, and no more than a stated size. A device such as `/dev/zero` would be
//! read until memory runs out, and a FIFO would block the open until a writer comes,
//! so both are refused before they are opened.

use std::io::{Error, ErrorKind, Read};
use std::path::Path;

/// Largest scene file: the bundled scenes hold a few kB; a scene typed or generated
/// with thousands of probes or polygon vertices stays far below. Parsing takes about
/// fifty times the text's size, so this also bounds what `check` holds.
pub const MAX_SCENE_BYTES: u64 = 1 << 20;

/// Largest mesh or terrain grid: 64 MiB is a binary STL of 1.3 million triangles or an
/// ASCII grid of several million heights, beyond what the particle fill handles in
/// reasonable time.
pub const MAX_SHAPE_FILE_BYTES: u64 = 64 << 20;

/// The bytes of the regular file `path`, refused when it is not a regular file or
/// holds more than `cap` bytes (also when it grows past `cap` while it is read).
pub fn read_capped(path: &Path, cap: u64) -> Result<Vec<u8>, Error> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "not a regular file (a device, FIFO or directory cannot be read as one)",
        ));
    }
    let too_big = |n: u64| {
        Error::new(
            ErrorKind::InvalidData,
            format!(
                "{} MiB, over the {} MiB such a file may hold",
                shortest_mib(n),
                cap >> 20
            ),
        )
    };
    if meta.len() > cap {
        return Err(too_big(meta.len()));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)?
        .take(cap + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > cap {
        return Err(too_big(bytes.len() as u64));
    }
    Ok(bytes)
}

/// [`read_capped`] as UTF-8 text.
pub fn read_capped_text(path: &Path, cap: u64) -> Result<String, Error> {
    String::from_utf8(read_capped(path, cap)?)
        .map_err(|_| Error::new(ErrorKind::InvalidData, "stream did not contain valid UTF-8"))
}

/// Bytes in MiB with one decimal.
fn shortest_mib(n: u64) -> String {
    format!("{:.1}", n as f64 / (1u64 << 20) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_and_directories_are_refused_and_files_capped() {
        let e = read_capped(Path::new("/dev/zero"), 10).unwrap_err();
        assert!(e.to_string().contains("not a regular file"), "{e}");
        assert!(read_capped(Path::new("/"), 10).is_err());
        let p = std::env::temp_dir().join(format!("granmix_capped_{}", std::process::id()));
        std::fs::write(&p, b"0123456789").unwrap();
        assert_eq!(read_capped(&p, 10).unwrap().len(), 10);
        let e = read_capped(&p, 9).unwrap_err();
        assert!(e.to_string().contains("over the 0 MiB"), "{e}");
        std::fs::remove_file(&p).ok();
    }
}
