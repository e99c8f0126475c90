//! The output file, written atomically: into a temporary file beside it,
//! renamed over it only when the program is whole, so a reader never sees
//! half a program and on an error the old file stays. A device or a FIFO
//! (a machine's) is sent the program once it is whole, never replaced.
//! With the [`super::fs::FileSystem`] view, the only place the library
//! touches the file system.

use super::compile::Report;
use std::io::{Seek, Write};
use std::path::{Path, PathBuf};

/// An unnamed temporary file to hold an output until it is known whole
/// (what goes to standard output): memory stays bounded.
pub fn held_file() -> std::io::Result<std::fs::File> {
    tempfile::tempfile()
}

/// Write a file through `write`, atomically: into a temporary file beside
/// it, renamed on success; on failure the old file stays.
pub fn write_file<T>(
    path: &Path,
    write: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<T>,
) -> std::io::Result<T> {
    let (path, tmp, file) = match destination(path)? {
        Destination::Device(path) => {
            // Never replaced: written as it is opened.
            let device = std::fs::OpenOptions::new().write(true).open(path)?;
            let mut out = std::io::BufWriter::new(device);
            let value = write(&mut out)?;
            out.flush()?;
            return Ok(value);
        }
        Destination::Replacing {
            path, tmp, file, ..
        } => (path, tmp, file),
    };
    let mut out = std::io::BufWriter::new(file);
    let result = write(&mut out).and_then(|value| {
        let file = out.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        std::fs::rename(&tmp, &path)?;
        Ok(value)
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Where a new file for a path given goes.
enum Destination {
    /// A device or a FIFO ([`is_device`]): opened and written, never
    /// replaced.
    Device(PathBuf),
    /// A file, or nothing yet: written to `tmp` beside it
    /// ([`create_replacing`]), then renamed over it. `replaces`: there is
    /// a file there now.
    Replacing {
        path: PathBuf,
        tmp: PathBuf,
        file: std::fs::File,
        replaces: bool,
    },
}

/// The [`Destination`] for `path`, through its links ([`through_links`]).
fn destination(path: &Path) -> std::io::Result<Destination> {
    let path = through_links(path)?;
    if is_device(&path) {
        return Ok(Destination::Device(path));
    }
    let tmp = temporary_beside(&path);
    let (file, replaces) = create_replacing(&tmp, &path)?;
    Ok(Destination::Replacing {
        path,
        tmp,
        file,
        replaces,
    })
}

/// The file `path` names, through symbolic links: the new file replaces
/// the link's target, and the link stays (a link to the folder a machine
/// reads its programs from keeps pointing there, and the machine gets the
/// new program, not the old one). A chain of more than 40 links is an
/// error.
fn through_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut path = path.to_path_buf();
    for _ in 0..40 {
        let Ok(target) = std::fs::read_link(&path) else {
            // Not a link (or nothing there yet).
            return Ok(path);
        };
        path = match path.parent() {
            Some(folder) if target.is_relative() => folder.join(target),
            _ => target,
        };
    }
    Err(std::io::Error::other(format!(
        "`{}`: too many symbolic links",
        path.display()
    )))
}

/// Whether `path` names something other than a file or a folder: a
/// device (`/dev/null`), a FIFO, a socket. Writing it means opening it,
/// never replacing it.
fn is_device(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Compile into a held copy (an unnamed temporary file, else memory) and
/// write it to the device `path` only when it is whole, as standard output
/// is written: a machine on a FIFO never gets half a program, and on an
/// error it gets nothing.
fn write_when_whole(
    path: &Path,
    compile: impl FnOnce(&mut (dyn Write + Send)) -> Report,
) -> Report {
    let open = || std::fs::OpenOptions::new().write(true).open(path);
    let (report, written) = match tempfile::tempfile() {
        Ok(mut held) => {
            let report = compile(&mut held);
            let copy = |held: &mut std::fs::File| {
                held.seek(std::io::SeekFrom::Start(0))?;
                std::io::copy(held, &mut open()?).map(|_| ())
            };
            let written = report.succeeded().then(|| copy(&mut held));
            (report, written)
        }
        Err(_) => {
            let mut text = Vec::new();
            let report = compile(&mut text);
            let written = report.succeeded().then(|| open()?.write_all(&text));
            (report, written)
        }
    };
    let mut report = report;
    if let Some(Err(e)) = written {
        report.write_error = Some(e);
    }
    report
}

/// Create the file `tmp` that is to replace `path`, with `path`'s
/// permissions if it exists (a program a machine's account may read stays
/// readable to it), and say whether a file is there to be replaced.
fn create_replacing(tmp: &Path, path: &Path) -> std::io::Result<(std::fs::File, bool)> {
    let file = std::fs::File::create(tmp)?;
    let old = std::fs::metadata(path).ok().filter(|old| old.is_file());
    if let Some(old) = &old {
        let done = file.set_permissions(old.permissions());
        if let Err(e) = done {
            let _ = std::fs::remove_file(tmp);
            return Err(e);
        }
    }
    Ok((file, old.is_some()))
}

/// A temporary file's name beside `path` (same folder, so that the rename
/// that replaces `path` is atomic).
fn temporary_beside(path: &Path) -> PathBuf {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    dir.join(format!(".{file_name}.{}.tmp", std::process::id()))
}

pub fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// A file being written whose pages go to the disk as it grows: after each
/// [`EarlyWriteback::EVERY`] bytes the kernel is asked to start writing them,
/// without waiting, so that the `sync_all` before the rename finds little
/// left to write (ARCHITECTURE.md, "Bird's-eye view"). `sync_all` still says
/// whether every write reached the disk.
struct EarlyWriteback<'f> {
    file: &'f mut std::fs::File,
    /// Bytes written and handed to the kernel's writeback, and since.
    started: u64,
    since: u64,
    /// The file the new one will replace, if there is one: its cached
    /// pages are let go of at the first writeback ([`let_go_of`]).
    #[cfg_attr(not(target_os = "linux"), allow(dead_code))]
    old: Option<&'f Path>,
}

impl<'f> EarlyWriteback<'f> {
    const EVERY: u64 = 1 << 18;

    fn new(file: &'f mut std::fs::File, old: Option<&'f Path>) -> EarlyWriteback<'f> {
        EarlyWriteback {
            file,
            started: 0,
            since: 0,
            old,
        }
    }

    /// Start the writeback of the bytes written since the last time. On
    /// Linux, `POSIX_FADV_DONTNEED` on dirty pages starts their writeback
    /// and returns (what PostgreSQL uses where `sync_file_range` is
    /// missing); it drops only pages already clean, so these stay cached.
    /// Elsewhere the sync before the rename writes it all.
    fn start_writeback(&mut self) {
        #[cfg(target_os = "linux")]
        {
            let advice = rustix::fs::Advice::DontNeed;
            // Only a hint: an error here is the final sync's to report.
            let _ = rustix::fs::fadvise(
                &*self.file,
                self.started,
                std::num::NonZeroU64::new(self.since),
                advice,
            );
            if let Some(old) = self.old.take() {
                let_go_of(old);
            }
        }
        self.started += self.since;
        self.since = 0;
    }
}

/// Ask the kernel to drop the cached pages of the file `old`, which the
/// output is about to replace. The rename that replaces it frees them
/// otherwise, on the compile's last step; let go of while the compile
/// still runs, on the back end's thread (which has room), they cost the
/// end nothing: 200k moves with `-o`, 1.2 ms faster at the median
/// (ARCHITECTURE.md, "The eleventh stop"). Only clean pages are dropped,
/// and the file is not changed: if the compile then fails, it stays as
/// it was. Opened without blocking (a FIFO put there since the start
/// would wait for a writer) and let go of only if it is a plain file.
#[cfg(target_os = "linux")]
fn let_go_of(old: &Path) {
    use rustix::fs::{FileType, Mode, OFlags};
    let flags = OFlags::RDONLY | OFlags::NONBLOCK | OFlags::CLOEXEC;
    let Ok(fd) = rustix::fs::open(old, flags, Mode::empty()) else {
        return;
    };
    let plain = rustix::fs::fstat(&fd)
        .is_ok_and(|s| FileType::from_raw_mode(s.st_mode) == FileType::RegularFile);
    if plain {
        // Only a hint, as the writeback's.
        let _ = rustix::fs::fadvise(&fd, 0, None, rustix::fs::Advice::DontNeed);
    }
}

impl Write for EarlyWriteback<'_> {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(bytes)?;
        self.since += n as u64;
        if self.since >= Self::EVERY {
            self.start_writeback();
        }
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

/// Compile into a temporary file beside the target, then rename it on
/// success: a reader never sees half a program, and on failure (errors in
/// the program, or in writing) the old file stays. A target that is not a
/// file (`/dev/null`, a FIFO to a machine) is never replaced: it is sent
/// the program once it is whole ([`write_when_whole`]).
pub fn write_atomically(
    path: &Path,
    compile: impl FnOnce(&mut (dyn Write + Send)) -> Report,
) -> Report {
    let (path, tmp, mut file, replaces) = match destination(path) {
        Ok(Destination::Device(path)) => return write_when_whole(&path, compile),
        Ok(Destination::Replacing {
            path,
            tmp,
            file,
            replaces,
        }) => (path, tmp, file, replaces),
        Err(e) => {
            // Still compile, for the diagnostics.
            let mut report = compile(&mut std::io::sink());
            report.write_error = Some(e);
            return report;
        }
    };
    // The file it replaces, if any (on Linux its pages are let go of as
    // the compile runs).
    let old = replaces.then_some(path.as_path());
    let mut report = compile(&mut EarlyWriteback::new(&mut file, old));
    if report.succeeded() {
        if let Err(e) = file.sync_all().and_then(|()| std::fs::rename(&tmp, &path)) {
            report.write_error = Some(e);
        }
    }
    if !report.succeeded() {
        let _ = std::fs::remove_file(&tmp);
    }
    report
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    /// Letting go of the old output's pages never waits: a FIFO put where
    /// the old file was (after the first look) is not opened for a writer
    /// to come, and a file is left as it was.
    #[test]
    fn letting_go_of_the_old_output_neither_waits_nor_changes_it() {
        let dir = std::env::temp_dir().join(format!("ger-let-go-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("machine");
        let _ = std::fs::remove_file(&fifo);
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.is_ok_and(|s| s.success()), "mkfifo");
        let (done, finished) = std::sync::mpsc::channel();
        let path = fifo.clone();
        std::thread::spawn(move || {
            let_go_of(&path);
            let _ = done.send(());
        });
        let waited = finished.recv_timeout(std::time::Duration::from_secs(10));
        assert!(waited.is_ok(), "waiting on the FIFO for a writer");

        let file = dir.join("old.nc");
        std::fs::write(&file, "G0 X1\n").unwrap();
        let_go_of(&file);
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "G0 X1\n");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
