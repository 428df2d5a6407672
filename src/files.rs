//! Crash-safe file writing: whatever happens while a file is written (a full disk, a read-only
//! file system, an I/O error, the process killed), the file that was there before survives
//! whole, and no error goes unreported.
//!
//! The bytes go to a temporary file in the target's directory (so the final rename stays on one
//! file system), which is flushed and fsynced, every error checked, and then renamed over the
//! target; the directory is fsynced so that the rename itself is durable. A target that exists
//! and is not a regular file (a device such as `/dev/full` or `/dev/null`, a FIFO) cannot be
//! replaced by renaming: it is written in place, still with every error checked.

use std::fs::{File, Permissions};
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

/// Prefix of the temporary files, which a killed process may leave behind (`.timbre-*.tmp`).
pub const TEMPORARY_PREFIX: &str = ".timbre-";

/// The directory a file at `path` is written in (`.` for a bare file name).
fn directory(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// The file a symbolic link at `path` points to, if it is one that resolves: that file is
/// replaced and the link kept.
fn resolve(path: &Path) -> Option<PathBuf> {
    let linked = std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink());
    linked.then(|| std::fs::canonicalize(path).ok()).flatten()
}

/// A file being written crash-safely (see the module docs): [`Write`] and [`Seek`] go to a
/// temporary file, which [`AtomicFile::commit`] flushes, fsyncs and renames over the target.
/// Dropped without a commit, it leaves the target as it was and removes the temporary file.
pub struct AtomicFile {
    target: PathBuf,
    out: BufWriter<Spool>,
}

/// Where the bytes go until the commit: a named temporary file beside the target, or, for a
/// device or FIFO target (written in place at the commit), an unnamed one.
enum Spool {
    Beside(tempfile::NamedTempFile),
    ForDevice(File),
}

impl Spool {
    fn file(&mut self) -> &mut File {
        match self {
            Spool::Beside(t) => t.as_file_mut(),
            Spool::ForDevice(f) => f,
        }
    }
}

impl AtomicFile {
    /// Starts writing the file at `path` (a symbolic link is followed: the file it points to is
    /// replaced and the link kept).
    pub fn create(path: &Path) -> io::Result<AtomicFile> {
        let resolved = resolve(path);
        let target = resolved.unwrap_or_else(|| path.to_path_buf());
        let existing = std::fs::metadata(&target).ok();
        let spool = if existing.as_ref().is_some_and(|m| !m.is_file()) {
            // Must open for writing, found out now rather than at the end.
            File::options().write(true).open(&target)?;
            Spool::ForDevice(tempfile::tempfile()?)
        } else {
            // A new file gets the usual permissions, a replaced one keeps its own.
            let permissions = existing.map_or(Permissions::from_mode(0o644), |m| m.permissions());
            Spool::Beside(
                tempfile::Builder::new()
                    .prefix(TEMPORARY_PREFIX)
                    .suffix(".tmp")
                    .permissions(permissions)
                    .tempfile_in(directory(&target))?,
            )
        };
        Ok(AtomicFile {
            target,
            out: BufWriter::new(spool),
        })
    }

    /// The bytes written so far, as a file to read and patch (flushed first).
    pub fn written(&mut self) -> io::Result<&mut File> {
        self.out.flush()?;
        Ok(self.out.get_mut().file())
    }

    /// Publishes the file: flushed and fsynced, every error checked, renamed over the target
    /// and the directory fsynced (a device or FIFO target is written in place instead).
    pub fn commit(self) -> io::Result<()> {
        let spool = self.out.into_inner().map_err(|e| e.into_error())?;
        match spool {
            Spool::Beside(temporary) => {
                temporary.as_file().sync_all()?;
                temporary.persist(&self.target).map_err(|e| e.error)?;
                File::open(directory(&self.target))?.sync_all()
            }
            Spool::ForDevice(mut spool) => {
                spool.seek(SeekFrom::Start(0))?;
                let mut device = File::options().write(true).open(&self.target)?;
                io::copy(&mut spool, &mut device)?;
                device.sync_all().or_else(|e| {
                    // Devices and FIFOs need not support fsync; that is not a failed write.
                    if e.kind() == io::ErrorKind::InvalidInput {
                        Ok(())
                    } else {
                        Err(e)
                    }
                })
            }
        }
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.out.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

impl Seek for AtomicFile {
    fn seek(&mut self, to: SeekFrom) -> io::Result<u64> {
        self.out.seek(to)
    }
}

impl Write for Spool {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.file().write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file().flush()
    }
}

impl Seek for Spool {
    fn seek(&mut self, to: SeekFrom) -> io::Result<u64> {
        self.file().seek(to)
    }
}

/// Writes the file at `path` with `write`, crash-safely ([`AtomicFile`]): the file at `path` is
/// replaced only if `write` and every step after it succeed.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> io::Result<()> {
    let mut file = AtomicFile::create(path)?;
    write(&mut file)?;
    file.commit()
}

/// Opens the regular file at `path` for reading: a FIFO, a device, a socket or a directory is
/// refused before it is opened (opening or reading one could block forever or never end).
pub fn open_regular(path: &Path) -> io::Result<File> {
    use std::os::unix::fs::FileTypeExt;
    let kind = std::fs::metadata(path)?.file_type();
    let not = |what: &str| {
        Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("is {what}, not a regular file"),
        ))
    };
    if kind.is_dir() {
        return not("a directory");
    }
    if kind.is_fifo() {
        return not("a FIFO (named pipe)");
    }
    if kind.is_socket() {
        return not("a socket");
    }
    if kind.is_char_device() || kind.is_block_device() {
        return not("a device");
    }
    File::open(path)
}

/// Reads the whole regular file at `path` ([`open_regular`]), at most `limit` bytes: a larger
/// file is refused, its size checked before reading and again while reading (a file that grows
/// meanwhile).
pub fn read_regular(path: &Path, limit: u64) -> io::Result<Vec<u8>> {
    use std::io::Read;
    let file = open_regular(path)?;
    let too_large = |size: u64| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("is larger than the limit of {limit} bytes ({size} bytes or more)"),
        )
    };
    let size = file.metadata()?.len();
    if size > limit {
        return Err(too_large(size));
    }
    let mut bytes = Vec::new();
    file.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

/// Checks that files can be created in the directory of `path` (it exists, is a directory and
/// is writable), by creating and removing a temporary file there: before a long render, not
/// after it.
pub fn check_writable(path: &Path) -> io::Result<()> {
    let resolved = resolve(path);
    let path = resolved.as_deref().unwrap_or(path);
    let dir = directory(path);
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
        // Written in place: it must open for writing.
        return File::options().write(true).open(path).map(drop);
    }
    tempfile::Builder::new()
        .prefix(TEMPORARY_PREFIX)
        .suffix(".probe")
        .tempfile_in(dir)
        .map(drop)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("picture.png");
        write_atomically(&path, |out| out.write_all(b"old")).unwrap();
        let failed = write_atomically(&path, |out| {
            out.write_all(b"new, but")?;
            Err(io::Error::other("the encoder failed"))
        });
        assert_eq!(failed.unwrap_err().to_string(), "the encoder failed");
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["picture.png"], "the temporary file is removed");
        write_atomically(&path, |out| out.write_all(b"new")).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
    }

    #[test]
    fn a_replaced_file_keeps_its_permissions_and_a_new_one_gets_0644() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        write_atomically(&path, |out| out.write_all(b"1")).unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&path), 0o644);
        std::fs::set_permissions(&path, Permissions::from_mode(0o600)).unwrap();
        write_atomically(&path, |out| out.write_all(b"2")).unwrap();
        assert_eq!(mode(&path), 0o600);
    }

    #[test]
    fn a_link_is_followed_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("renders").join("v1.png");
        std::fs::create_dir(target.parent().unwrap()).unwrap();
        std::fs::write(&target, b"old").unwrap();
        let link = dir.path().join("latest.png");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        write_atomically(&link, |out| out.write_all(b"new")).unwrap();
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
    }

    #[test]
    fn only_regular_files_within_the_limit_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("scene.toml");
        std::fs::write(&path, b"0123456789").unwrap();
        assert_eq!(read_regular(&path, 10).unwrap(), b"0123456789");
        let e = read_regular(&path, 9).unwrap_err().to_string();
        assert!(e.contains("larger than the limit of 9 bytes"), "{e}");
        let e = read_regular(dir.path(), 100).unwrap_err().to_string();
        assert!(e.contains("a directory"), "{e}");
        for (device, what) in [("/dev/zero", "a device"), ("/dev/null", "a device")] {
            if Path::new(device).exists() {
                let e = read_regular(Path::new(device), 100)
                    .unwrap_err()
                    .to_string();
                assert!(e.contains(what), "{device}: {e}");
            }
        }
        // A FIFO would block the open until someone writes to it.
        let fifo = dir.path().join("fifo");
        if std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .is_ok_and(|s| s.success())
        {
            let e = read_regular(&fifo, 100).unwrap_err().to_string();
            assert!(e.contains("FIFO"), "{e}");
        }
    }

    #[test]
    fn a_full_device_is_an_error() {
        let full = Path::new("/dev/full");
        if !full.exists() {
            return;
        }
        let e = write_atomically(full, |out| out.write_all(&[0; 1 << 16])).unwrap_err();
        assert_eq!(e.raw_os_error(), Some(28), "ENOSPC: {e}");
        assert!(full.exists(), "the device is not replaced");
    }
}
