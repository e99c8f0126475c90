//! The file-system view a compile reads through: the disk for the
//! binary, an editor's open buffers over the disk for the editor server,
//! a map of names to texts for the tests. The library reads files only
//! through this trait (Gleam's `io` module is the model).

use std::collections::BTreeMap;
use std::io::{self, BufRead, Seek};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// What a compile may read: files whole or a part at a time, the names in
/// a folder, and a file's stamp (to tell whether it changed while it was
/// read).
pub trait FileSystem: Sync {
    fn read(&self, path: &Path) -> io::Result<Vec<u8>>;

    /// The file as a reader, for a program compiled a part at a time
    /// (and scanned from its middle, [`super::scan::scan_path`]).
    fn open(&self, path: &Path) -> io::Result<Box<dyn Reader + '_>>;

    /// The paths of the entries of the folder `dir`, in no set order.
    fn list(&self, dir: &Path) -> io::Result<Vec<PathBuf>>;

    fn is_file(&self, path: &Path) -> bool;

    fn is_dir(&self, path: &Path) -> bool;

    /// The file's stamp; `None` where the view has none (a buffer).
    fn stamp(&self, path: &Path) -> io::Result<Option<Stamp>>;
}

/// A file opened for reading in parts: buffered, and able to start in
/// its middle.
pub trait Reader: BufRead + Seek {}

impl<T: BufRead + Seek> Reader for T {}

/// A file's length and modification time, and whether it is a plain file
/// (a pipe cannot be read twice).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stamp {
    pub len: u64,
    pub modified: Option<SystemTime>,
    pub plain: bool,
}

/// The disk, as the process sees it.
#[derive(Clone, Copy, Debug, Default)]
pub struct Disk;

impl FileSystem for Disk {
    fn read(&self, path: &Path) -> io::Result<Vec<u8>> {
        std::fs::read(path)
    }

    fn open(&self, path: &Path) -> io::Result<Box<dyn Reader + '_>> {
        let file = std::fs::File::open(path)?;
        Ok(Box::new(io::BufReader::with_capacity(1 << 16, file)))
    }

    fn list(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        std::fs::read_dir(dir)?
            .map(|entry| entry.map(|e| e.path()))
            .collect()
    }

    fn is_file(&self, path: &Path) -> bool {
        path.is_file()
    }

    fn is_dir(&self, path: &Path) -> bool {
        path.is_dir()
    }

    fn stamp(&self, path: &Path) -> io::Result<Option<Stamp>> {
        let meta = std::fs::metadata(path)?;
        Ok(Some(Stamp {
            len: meta.len(),
            modified: meta.modified().ok(),
            plain: meta.is_file(),
        }))
    }
}

/// Files held in memory by path: a test's files, or an editor's open
/// buffers. Folders are the paths' parents. With a `fallback`, a path it
/// does not hold is read there (an editor's buffers over the disk).
#[derive(Default)]
pub struct Memory<'a> {
    files: BTreeMap<PathBuf, Vec<u8>>,
    fallback: Option<&'a dyn FileSystem>,
}

impl<'a> Memory<'a> {
    pub fn new() -> Memory<'a> {
        Memory::default()
    }

    /// Held files over `fallback`: what is not held is read there.
    pub fn over(fallback: &'a dyn FileSystem) -> Memory<'a> {
        Memory {
            files: BTreeMap::new(),
            fallback: Some(fallback),
        }
    }

    /// Hold `text` as the file `path` (replacing what was held).
    pub fn insert(&mut self, path: impl Into<PathBuf>, text: impl Into<Vec<u8>>) {
        self.files.insert(path.into(), text.into());
    }

    pub fn remove(&mut self, path: &Path) {
        self.files.remove(path);
    }

    fn held(&self, path: &Path) -> Option<&[u8]> {
        self.files.get(path).map(Vec::as_slice)
    }

    fn not_held<T>(path: &Path) -> io::Result<T> {
        Err(io::Error::new(
            io::ErrorKind::NotFound,
            format!("`{}` is not held", path.display()),
        ))
    }
}

impl FileSystem for Memory<'_> {
    fn read(&self, path: &Path) -> io::Result<Vec<u8>> {
        match (self.held(path), self.fallback) {
            (Some(bytes), _) => Ok(bytes.to_vec()),
            (None, Some(fallback)) => fallback.read(path),
            (None, None) => Memory::not_held(path),
        }
    }

    fn open(&self, path: &Path) -> io::Result<Box<dyn Reader + '_>> {
        match (self.held(path), self.fallback) {
            (Some(bytes), _) => Ok(Box::new(io::Cursor::new(bytes))),
            (None, Some(fallback)) => fallback.open(path),
            (None, None) => Memory::not_held(path),
        }
    }

    fn list(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        let mut found: Vec<PathBuf> = self
            .files
            .keys()
            .filter(|p| p.parent() == Some(dir))
            .cloned()
            .collect();
        let listed = match self.fallback {
            Some(fallback) => fallback.list(dir),
            None if found.is_empty() && !self.is_dir(dir) => Memory::not_held(dir),
            None => Ok(Vec::new()),
        };
        match listed {
            Ok(more) => {
                found.extend(more.into_iter().filter(|p| !self.files.contains_key(p)));
                Ok(found)
            }
            Err(_) if !found.is_empty() => Ok(found),
            Err(e) => Err(e),
        }
    }

    fn is_file(&self, path: &Path) -> bool {
        self.files.contains_key(path) || self.fallback.is_some_and(|f| f.is_file(path))
    }

    fn is_dir(&self, path: &Path) -> bool {
        self.files.keys().any(|p| p.starts_with(path) && p != path)
            || self.fallback.is_some_and(|f| f.is_dir(path))
    }

    fn stamp(&self, path: &Path) -> io::Result<Option<Stamp>> {
        match (self.held(path), self.fallback) {
            // A held text is not a file on disk: it is never read in parts.
            (Some(_), _) => Ok(None),
            (None, Some(fallback)) => fallback.stamp(path),
            (None, None) => Memory::not_held(path),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn held_files_list_by_folder_and_fall_back_to_the_view_below() {
        let mut below = Memory::new();
        below.insert("/p/wizards/Old.rhai", "old");
        below.insert("/p/wizards/Kept.rhai", "kept");
        let mut over = Memory::over(&below);
        over.insert("/p/wizards/Old.rhai", "new");
        over.insert("/p/part.egc", "G0 X1");
        assert_eq!(over.read(Path::new("/p/wizards/Old.rhai")).unwrap(), b"new");
        assert_eq!(
            over.read(Path::new("/p/wizards/Kept.rhai")).unwrap(),
            b"kept"
        );
        let mut listed = over.list(Path::new("/p/wizards")).unwrap();
        listed.sort();
        assert_eq!(
            listed,
            [
                PathBuf::from("/p/wizards/Kept.rhai"),
                PathBuf::from("/p/wizards/Old.rhai")
            ]
        );
        assert!(over.is_dir(Path::new("/p")) && !over.is_dir(Path::new("/q")));
        assert!(over.read(Path::new("/p/missing.egc")).is_err());
        assert_eq!(over.stamp(Path::new("/p/part.egc")).unwrap(), None);
        let mut text = String::new();
        over.open(Path::new("/p/part.egc"))
            .unwrap()
            .read_to_string(&mut text)
            .unwrap();
        assert_eq!(text, "G0 X1");
    }
}
