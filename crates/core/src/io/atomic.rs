//! Writes that leave no half-written output: write to `NAME.tmp` beside the target, then rename.

use crate::error::WakelabError;
use std::path::{Path, PathBuf};

/// A file being written at a temporary path; [`AtomicFile::commit`] renames it into place and
/// dropping it uncommitted removes the temporary file.
#[derive(Debug)]
pub struct AtomicFile {
    target: PathBuf,
    temporary: PathBuf,
    committed: bool,
}

impl AtomicFile {
    /// Reserve `target`; creates its parent directory.
    pub fn new(target: impl AsRef<Path>) -> Result<Self, WakelabError> {
        let target = target.as_ref().to_path_buf();
        if let Some(parent) = target.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent).map_err(|e| WakelabError::io(parent, e))?;
        }
        let mut name = target.file_name().unwrap_or_default().to_os_string();
        name.push(".tmp");
        let temporary = target.with_file_name(name);
        Ok(Self {
            target,
            temporary,
            committed: false,
        })
    }

    /// Where to write now.
    pub fn temporary_path(&self) -> &Path {
        &self.temporary
    }

    /// Where the file will be once committed.
    pub fn target_path(&self) -> &Path {
        &self.target
    }

    /// Rename the finished temporary file into place.
    pub fn commit(mut self) -> Result<PathBuf, WakelabError> {
        std::fs::rename(&self.temporary, &self.target).map_err(|e| WakelabError::io(&self.target, e))?;
        self.committed = true;
        Ok(self.target.clone())
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_file(&self.temporary);
        }
    }
}

/// Write `bytes` to `path` atomically.
pub fn write_atomically(path: impl AsRef<Path>, bytes: &[u8]) -> Result<PathBuf, WakelabError> {
    let file = AtomicFile::new(path)?;
    std::fs::write(file.temporary_path(), bytes).map_err(|e| WakelabError::io(file.temporary_path(), e))?;
    file.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uncommitted_file_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out.txt");
        {
            let f = AtomicFile::new(&target).unwrap();
            std::fs::write(f.temporary_path(), b"half").unwrap();
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        write_atomically(&target, b"whole").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"whole");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
