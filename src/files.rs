//! Crash-safe file writing: whatever happens while a file is written (a full disk, a read-only
//! file system, a file-size limit, an I/O error, the process killed), the file that was there
//! before survives whole, and no error goes unreported.
//!
//! The bytes go to a temporary file in the target's directory (so the final rename stays on one
//! file system), which is flushed and fsynced, every error checked, and then renamed over the
//! target; the directory is fsynced so that the rename itself is durable. A target that exists
//! and is not a regular file (a device such as `/dev/full` or `/dev/null`, a FIFO) cannot be
//! replaced by renaming: it is written in place, still with every error checked.
//!
//! A temporary file is named after its target and its writer, `.NAME.timbre-PID-SPACE-XXXXXX.tmp`
//! ([`temporary_prefix`]): NAME the target's file name, PID the writing process, SPACE a tag
//! of where that process id means that process (the machine, its boot and the process-id
//! namespace), XXXXXX random. A process killed outright (`kill -9`, a power cut) cannot remove
//! its temporary file, so every writer first removes those of the same target whose process,
//! in the same SPACE, no longer exists ([`remove_stale`]); nothing else is touched.

use std::ffi::{OsStr, OsString};
use std::fs::{File, Permissions};
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::os::unix::ffi::{OsStrExt, OsStringExt};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// What follows the target's name in a temporary file's name (`.NAME.timbre-…`).
const MARK: &str = ".timbre-";
/// The end of a temporary file's name.
const SUFFIX: &str = ".tmp";
/// Random characters that end a temporary file's name before [`SUFFIX`].
const RANDOM: usize = 6;
/// The longest file name Linux file systems take (`NAME_MAX`).
const NAME_MAX: usize = 255;
/// The longest target name used whole in a temporary file's name: what is left of
/// [`NAME_MAX`] after the dot, the mark, a process id of up to 10 digits, the 8-digit tag, two
/// dashes, the random characters and the suffix.
const LONGEST_NAME: usize = NAME_MAX - 1 - MARK.len() - 10 - 1 - 8 - 1 - RANDOM - SUFFIX.len();

/// 64-bit FNV-1a: a hash that is the same in every build and process.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Where this process's id means this process, as 8 hex digits: a hash of the host name, the
/// boot (`/proc/sys/kernel/random/boot_id`) and the process-id namespace
/// (`/proc/self/ns/pid`). A process id in another machine's temporary file (on a shared file
/// system), from before a reboot or from another container says nothing about the processes
/// here, so such a file is never taken for stale.
fn process_space() -> &'static str {
    static SPACE: OnceLock<String> = OnceLock::new();
    SPACE.get_or_init(|| {
        let mut key = nix::unistd::gethostname().unwrap_or_default().into_vec();
        key.push(0);
        key.extend(std::fs::read("/proc/sys/kernel/random/boot_id").unwrap_or_default());
        key.push(0);
        let namespace = std::fs::read_link("/proc/self/ns/pid").unwrap_or_default();
        key.extend(namespace.as_os_str().as_bytes());
        format!("{:08x}", fnv1a(&key) >> 32)
    })
}

/// The target's name as it starts its temporary files' names: whole, or, if longer than
/// [`LONGEST_NAME`] bytes, its start and a hash of the whole name (`~` and 16 hex digits).
fn name_in_temporary(target: &Path) -> OsString {
    let name = target.file_name().unwrap_or_default().as_bytes();
    if name.len() <= LONGEST_NAME {
        return OsStr::from_bytes(name).to_owned();
    }
    let mut short = name[..LONGEST_NAME - 17].to_vec();
    short.extend(format!("~{:016x}", fnv1a(name)).bytes());
    OsString::from_vec(short)
}

/// The start of the names of the temporary files of `target`, whoever writes them:
/// `.NAME.timbre-`.
fn temporary_start(target: &Path) -> OsString {
    let mut start = OsString::from(".");
    start.push(name_in_temporary(target));
    start.push(MARK);
    start
}

/// The start of the names of the temporary files that process `pid`, in this process's
/// process-id space, writes for `target`: `.NAME.timbre-PID-SPACE-` (random characters and
/// `.tmp` follow).
pub fn temporary_prefix(target: &Path, pid: u32) -> OsString {
    let mut prefix = temporary_start(target);
    prefix.push(format!("{pid}-{}-", process_space()));
    prefix
}

/// The process that wrote the file called `name`, if it is a temporary file written in this
/// process's process-id space: of the target whose temporary names start with `start`
/// ([`temporary_start`]), or of any target.
fn owner(name: &OsStr, start: Option<&OsStr>) -> Option<i32> {
    let name = name.as_bytes();
    let rest = match start {
        Some(start) => name.strip_prefix(start.as_bytes())?,
        None => {
            let mark = MARK.as_bytes();
            let at = name.windows(mark.len()).rposition(|w| w == mark)?;
            name.starts_with(b".").then_some(())?;
            &name[at + mark.len()..]
        }
    };
    let rest = std::str::from_utf8(rest.strip_suffix(SUFFIX.as_bytes())?).ok()?;
    let mut fields = rest.split('-');
    let (pid, space, random) = (fields.next()?, fields.next()?, fields.next()?);
    let random_ok = !random.is_empty() && random.bytes().all(|b| b.is_ascii_alphanumeric());
    if fields.next().is_some() || space != process_space() || !random_ok {
        return None;
    }
    if !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    // 0 and negative numbers would name process groups.
    pid.parse::<i32>().ok().filter(|&pid| pid > 0)
}

/// Whether process `pid` no longer exists (a process of another user still exists).
fn gone(pid: i32) -> bool {
    use nix::sys::signal::kill;
    use nix::unistd::Pid;
    kill(Pid::from_raw(pid), None) == Err(nix::errno::Errno::ESRCH)
}

/// Removes from `dir` the temporary files of `target` ([`temporary_prefix`]) left by processes
/// that no longer exist, in this process's process-id space: the files of a run killed
/// outright. Files of live processes, of other targets, of other machines, boots or
/// containers, and anything that is not a regular file are left alone. Removing is a
/// courtesy: a file that cannot be removed (a directory not readable, another user's file in a
/// sticky directory) is left without an error.
pub fn remove_stale(dir: &Path, target: &Path) {
    sweep(dir, Some(&temporary_start(target)));
}

/// Removes from `dir` the stale temporary files of every target, as [`remove_stale`] does for
/// one: for a directory that only timbre writes (a checkpoint).
pub fn remove_all_stale(dir: &Path) {
    sweep(dir, None);
}

/// Removes the stale temporary files in `dir` of the target whose temporary names start with
/// `start`, or of any target.
fn sweep(dir: &Path, start: Option<&OsStr>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let Some(pid) = owner(&entry.file_name(), start) else {
            continue;
        };
        let path = entry.path();
        let regular = std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_file());
        if regular && gone(pid) {
            let _ = std::fs::remove_file(&path);
        }
    }
}

/// A new temporary file for `target` in its directory, named by [`temporary_prefix`] (after
/// the stale ones of the target are removed).
fn temporary(target: &Path, permissions: Permissions) -> io::Result<tempfile::NamedTempFile> {
    let dir = directory(target);
    remove_stale(dir, target);
    tempfile::Builder::new()
        .prefix(&temporary_prefix(target, std::process::id()))
        .suffix(SUFFIX)
        .rand_bytes(RANDOM)
        .permissions(permissions)
        .tempfile_in(dir)
}

/// `e`, explained if it is `EFBIG` (the file grew past the file-size limit, `RLIMIT_FSIZE`, or
/// past what the file system holds). The `timbre` command handles `SIGXFSZ` (and the Python
/// interpreter ignores it), so that such a write fails with this error instead of the signal
/// killing the process.
pub fn explained(e: io::Error) -> io::Error {
    use nix::sys::resource::{RLIM_INFINITY, Resource, getrlimit};
    if e.raw_os_error() != Some(nix::libc::EFBIG) {
        return e;
    }
    let message = match getrlimit(Resource::RLIMIT_FSIZE) {
        Ok((limit, _)) if limit != RLIM_INFINITY => format!(
            "file too large: the file-size limit (RLIMIT_FSIZE, `ulimit -f`) of {limit} bytes was reached"
        ),
        _ => "file too large: larger than the file system allows".to_string(),
    };
    io::Error::new(io::ErrorKind::FileTooLarge, message)
}

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
            Spool::Beside(temporary(&target, permissions)?)
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
                io::copy(&mut spool, &mut device).map_err(explained)?;
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
        self.file().write(buf).map_err(explained)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file().flush().map_err(explained)
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
/// after it. Stale temporary files of the target are removed on the way ([`remove_stale`]).
pub fn check_writable(path: &Path) -> io::Result<()> {
    let resolved = resolve(path);
    let path = resolved.as_deref().unwrap_or(path);
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
        // Written in place: it must open for writing.
        return File::options().write(true).open(path).map(drop);
    }
    temporary(path, Permissions::from_mode(0o600)).map(drop)
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

    /// A process id no process has: beyond Linux's largest `pid_max` (2²²).
    const NO_PROCESS: u32 = (1 << 22) + 1;

    /// A temporary file's name as process `pid` would make it for `target`.
    fn temporary_name(target: &Path, pid: u32, random: &str) -> OsString {
        let mut name = temporary_prefix(target, pid);
        name.push(format!("{random}{SUFFIX}"));
        name
    }

    fn names(dir: &Path) -> Vec<OsString> {
        let mut names: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_temporary_file_is_named_after_its_target_and_its_process() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.exr");
        let mut file = AtomicFile::create(&path).unwrap();
        file.write_all(b"new").unwrap();
        let here = names(dir.path());
        assert_eq!(here.len(), 1);
        let name = here[0].to_str().unwrap();
        let prefix = temporary_prefix(&path, std::process::id());
        let random = name
            .strip_prefix(prefix.to_str().unwrap())
            .and_then(|r| r.strip_suffix(".tmp"))
            .unwrap_or_else(|| panic!("{name} is not {prefix:?}XXXXXX.tmp"));
        assert_eq!(random.len(), RANDOM, "{name}");
        assert!(name.starts_with(&format!(".out.exr.timbre-{}-", std::process::id())));
        // The file is its own process's: no writer takes it for stale.
        write_atomically(&path, |out| out.write_all(b"other")).unwrap();
        assert!(dir.path().join(name).exists());
        file.commit().unwrap();
        assert_eq!(names(dir.path()), ["out.exr"]);
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
    }

    #[test]
    fn a_writer_removes_the_stale_temporary_files_of_its_target_and_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out.exr");
        let stale = temporary_name(&target, NO_PROCESS, "AAAAAA");
        let make = |name: &OsStr| std::fs::write(dir.path().join(name), b"x").unwrap();
        make(&stale);
        let mut kept = vec![
            // Another target's, a live process's, and one from another machine, boot or
            // container (another process-id space).
            temporary_name(&dir.path().join("other.exr"), NO_PROCESS, "BBBBBB"),
            temporary_name(&dir.path().join("out"), NO_PROCESS, "BBBBBB"),
            temporary_name(&target, std::process::id(), "CCCCCC"),
            format!(".out.exr.timbre-{NO_PROCESS}-00000000-DDDDDD.tmp").into(),
            // Not the pattern: an older timbre's name, a process group, extra fields.
            ".timbre-EEEEEE.tmp".into(),
            format!(".out.exr.timbre-0-{}-FFFFFF.tmp", process_space()).into(),
            format!(
                ".out.exr.timbre-x-{NO_PROCESS}-{}-FFFFFF.tmp",
                process_space()
            )
            .into(),
            "notes.txt".into(),
        ];
        assert_ne!(process_space(), "00000000");
        for name in &kept {
            make(name);
        }
        // Named like a stale file but not a regular file: left alone.
        let directory = temporary_name(&target, NO_PROCESS, "GGGGGG");
        std::fs::create_dir(dir.path().join(&directory)).unwrap();
        let link = temporary_name(&target, NO_PROCESS, "HHHHHH");
        std::os::unix::fs::symlink("notes.txt", dir.path().join(&link)).unwrap();
        kept.extend([directory, link]);
        write_atomically(&target, |out| out.write_all(b"new")).unwrap();
        kept.push("out.exr".into());
        kept.sort();
        assert_eq!(names(dir.path()), kept);
        // The check before a render removes them too.
        make(&stale);
        check_writable(&target).unwrap();
        assert_eq!(names(dir.path()), kept);
    }

    #[test]
    fn a_directory_is_swept_of_every_target_s_stale_temporary_files() {
        let dir = tempfile::tempdir().unwrap();
        let at = |name: &str| dir.path().join(name);
        let stale = [
            temporary_name(&at("rows-0.exr"), NO_PROCESS, "AAAAAA"),
            temporary_name(&at("rows-32.exr"), NO_PROCESS, "BBBBBB"),
            temporary_name(&at("a.timbre-b.exr"), NO_PROCESS, "CCCCCC"),
        ];
        let kept: Vec<OsString> = vec![
            temporary_name(&at("rows-64.exr"), std::process::id(), "DDDDDD"),
            format!(".rows-0.exr.timbre-{NO_PROCESS}-00000000-EEEEEE.tmp").into(),
            format!(
                "rows-0.exr.timbre-{NO_PROCESS}-{}-FFFFFF.tmp",
                process_space()
            )
            .into(),
            "rows-0.exr".into(),
        ];
        for name in stale.iter().chain(&kept) {
            std::fs::write(dir.path().join(name), b"x").unwrap();
        }
        remove_all_stale(dir.path());
        let mut kept = kept;
        kept.sort();
        assert_eq!(names(dir.path()), kept);
    }

    #[test]
    fn a_long_target_name_is_shortened_in_its_temporary_files() {
        let dir = tempfile::tempdir().unwrap();
        let long = |end: &str| dir.path().join(format!("{}{end}", "a".repeat(240)));
        let (target, sibling) = (long("-1.exr"), long("-2.exr"));
        let prefix = temporary_prefix(&target, u32::MAX);
        assert!(
            prefix.len() + RANDOM + SUFFIX.len() <= NAME_MAX,
            "{prefix:?}"
        );
        assert_ne!(prefix, temporary_prefix(&sibling, u32::MAX));
        let stale = temporary_name(&target, NO_PROCESS, "AAAAAA");
        let other = temporary_name(&sibling, NO_PROCESS, "AAAAAA");
        for name in [&stale, &other] {
            std::fs::write(dir.path().join(name), b"x").unwrap();
        }
        write_atomically(&target, |out| out.write_all(b"new")).unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        assert!(!dir.path().join(&stale).exists());
        assert!(dir.path().join(&other).exists());
    }

    #[test]
    fn a_file_too_large_is_explained() {
        let e = explained(io::Error::from_raw_os_error(nix::libc::EFBIG));
        assert_eq!(e.kind(), io::ErrorKind::FileTooLarge);
        assert!(e.to_string().starts_with("file too large: "), "{e}");
        let other = explained(io::Error::from_raw_os_error(nix::libc::ENOSPC));
        assert_eq!(other.raw_os_error(), Some(nix::libc::ENOSPC));
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
