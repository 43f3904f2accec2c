//! The one place where files a user hands in are opened and where output files are
//! written, so that every reader refuses the same bad inputs with the same words and no
//! writer leaves a half-written file behind.
//!
//! Reading ([`InputFile::read`]): the file's type is checked before it is opened, because
//! opening a FIFO blocks and reading `/dev/zero` never ends; its size is capped (a
//! regular file may still grow while it is read, so the read itself stops at the cap);
//! an empty file is refused before any parser sees it, because parsers describe an
//! empty input by what it lacks (an ONNX file "of IR version 0"). Each refusal names
//! the path once; callers add no path of their own.
//!
//! Writing ([`Outputs`], [`write_atomically`]): every output goes to a temporary file
//! in its own directory and is renamed into place only when all outputs of a command
//! are complete, so that a command that fails leaves no new file and an older file of
//! the same name untouched. (A rename within one directory is atomic on the file
//! systems we run on; a copy is not.) A destination that exists and is no regular file
//! (`/dev/null`, `/dev/stdout`, a named pipe) is written straight into instead: a rename
//! would replace the device node or the pipe with a regular file (as root, `--out
//! /dev/null` would turn /dev/null into a file), and such a destination has no older
//! contents to keep.

use std::fmt;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// What kind of file a reader expects, for its messages, and how large it may be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InputFile {
    /// The kind of file in words ("weights file"), the first words of every message.
    pub what: &'static str,
    /// The largest accepted size in bytes.
    pub limit: u64,
}

const MIB: u64 = 1 << 20;

/// A network's weights: our JSON, ONNX or a law with memory's JSON. The paper's
/// 3 x 100 network is 0.65 MB of JSON; the cap leaves room for networks 400 times
/// larger, far past what a friction law evaluated every time step can afford.
pub const WEIGHTS_FILE: InputFile = InputFile {
    what: "weights file",
    limit: 256 * MIB,
};

/// A scene (TOML or JSON): a few kB of settings.
pub const SCENE_FILE: InputFile = InputFile {
    what: "scene file",
    limit: 16 * MIB,
};

/// Measured friction data (CSV) for training or for checking an imported network. The
/// paper authors' set is 0.8 MB; the cap keeps a mistaken file from filling memory.
pub const DATA_FILE: InputFile = InputFile {
    what: "data file",
    limit: 1024 * MIB,
};

/// Force records under velocity histories (CSV) for `train-memory`.
pub const RECORDS_FILE: InputFile = InputFile {
    what: "records file",
    limit: 1024 * MIB,
};

/// A structure's matrix or DOF map (CalculiX `.sti`/`.mas`/`.dof`, Matrix Market `.mtx`,
/// a DOF map file): about 30 bytes per stored entry, so the paper beam's K is 0.33 MB and
/// a 3D solid of 50,000 DOFs (about 2 million upper entries) near 60 MB; the cap leaves
/// room for 15 times that, past what the band factorisation accepts.
pub const STRUCTURE_FILE: InputFile = InputFile {
    what: "structure file",
    limit: 1024 * MIB,
};

/// Why an input file was refused. (An I/O error is kept as its message, so that errors
/// that hold this one, such as the scene's, stay `Clone` and `PartialEq`.)
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InputProblem {
    #[error("no such file")]
    Missing,
    #[error("is a directory, not a file")]
    Directory,
    /// A device, FIFO or socket: reading it may block or never end.
    #[error("is a {0}, not a regular file")]
    Special(&'static str),
    #[error("the file is empty")]
    Empty,
    #[error("{size} bytes, more than the {limit} bytes accepted")]
    TooLarge { size: u64, limit: u64 },
    #[error("cannot be read: permission denied")]
    PermissionDenied,
    #[error("cannot be read: {0}")]
    Unreadable(String),
    /// Text was expected; `offset` is the first byte that is not UTF-8.
    #[error("not UTF-8 text (byte {offset} is not part of a UTF-8 character)")]
    NotUtf8 { offset: usize },
}

/// An input file that was refused, with the path and the kind of file.
#[derive(Clone, Debug, PartialEq)]
pub struct InputFileError {
    pub what: &'static str,
    pub path: PathBuf,
    pub problem: InputProblem,
}

impl fmt::Display for InputFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}: {}", self.what, self.path.display(), self.problem)
    }
}

impl std::error::Error for InputFileError {}

impl InputFile {
    fn refuse(&self, path: &Path, problem: InputProblem) -> InputFileError {
        InputFileError {
            what: self.what,
            path: path.to_path_buf(),
            problem,
        }
    }

    fn refuse_io(&self, path: &Path, error: std::io::Error) -> InputFileError {
        let problem = match error.kind() {
            std::io::ErrorKind::NotFound => InputProblem::Missing,
            std::io::ErrorKind::PermissionDenied => InputProblem::PermissionDenied,
            std::io::ErrorKind::IsADirectory => InputProblem::Directory,
            _ => InputProblem::Unreadable(error.to_string()),
        };
        self.refuse(path, problem)
    }

    /// Checks, without opening it, that `path` is a regular file within the size limit
    /// (symbolic links followed): for a reader that opens it later, or to fail early.
    /// Emptiness is [`InputFile::read`]'s to judge: files of /proc report size 0 and
    /// have contents.
    pub fn check(&self, path: &Path) -> Result<(), InputFileError> {
        let metadata = std::fs::metadata(path).map_err(|e| self.refuse_io(path, e))?;
        let file_type = metadata.file_type();
        if file_type.is_dir() {
            return Err(self.refuse(path, InputProblem::Directory));
        }
        if !file_type.is_file() {
            return Err(self.refuse(path, InputProblem::Special(special_kind(&file_type))));
        }
        if metadata.len() > self.limit {
            return Err(self.refuse(
                path,
                InputProblem::TooLarge {
                    size: metadata.len(),
                    limit: self.limit,
                },
            ));
        }
        Ok(())
    }

    /// The bytes of the file at `path`, refused as [`InputFile::check`] refuses, or when
    /// it cannot be opened or read.
    pub fn read(&self, path: &Path) -> Result<Vec<u8>, InputFileError> {
        self.check(path)?;
        let file = std::fs::File::open(path).map_err(|e| self.refuse_io(path, e))?;
        let mut bytes = Vec::new();
        file.take(self.limit + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| self.refuse_io(path, e))?;
        let size = bytes.len() as u64;
        if size > self.limit {
            return Err(self.refuse(
                path,
                InputProblem::TooLarge {
                    size,
                    limit: self.limit,
                },
            ));
        }
        // A regular file reported with size 0 may still have contents (/proc files);
        // only what was read counts.
        if bytes.is_empty() {
            return Err(self.refuse(path, InputProblem::Empty));
        }
        Ok(bytes)
    }

    /// The text of the file at `path`: [`InputFile::read`], and refused when it is not
    /// UTF-8.
    pub fn read_text(&self, path: &Path) -> Result<String, InputFileError> {
        let bytes = self.read(path)?;
        self.text(path, bytes)
    }

    /// `bytes`, read from `path`, as UTF-8 text.
    pub fn text(&self, path: &Path, bytes: Vec<u8>) -> Result<String, InputFileError> {
        String::from_utf8(bytes).map_err(|e| {
            self.refuse(
                path,
                InputProblem::NotUtf8 {
                    offset: e.utf8_error().valid_up_to(),
                },
            )
        })
    }
}

#[cfg(unix)]
fn special_kind(file_type: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if file_type.is_char_device() {
        "character device"
    } else if file_type.is_block_device() {
        "block device"
    } else if file_type.is_fifo() {
        "FIFO (named pipe)"
    } else if file_type.is_socket() {
        "socket"
    } else {
        "special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_file_type: &std::fs::FileType) -> &'static str {
    "special file"
}

/// An output file that could not be written; nothing was put in its place.
#[derive(Debug, thiserror::Error)]
pub enum OutputFileError {
    #[error("cannot write {}: its directory does not exist", path.display())]
    MissingDirectory { path: PathBuf },
    #[error("cannot write {}: it is a directory", path.display())]
    Directory { path: PathBuf },
    #[error("cannot write {}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

impl OutputFileError {
    /// The output file at fault.
    pub fn path(&self) -> &Path {
        match self {
            OutputFileError::MissingDirectory { path }
            | OutputFileError::Directory { path }
            | OutputFileError::Io { path, .. } => path,
        }
    }
}

/// One output written to its temporary file, waiting to be renamed into place.
struct Staged {
    temporary: PathBuf,
    path: PathBuf,
}

/// Whether `destination` exists and is something other than a regular file (a device, a
/// pipe, a socket), which is written into rather than replaced.
fn is_special(destination: &Path) -> bool {
    std::fs::metadata(destination).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// The output files of one command: each is written to a temporary file beside its
/// destination with [`Outputs::add`]; [`Outputs::commit`] renames them all into place.
/// Dropped without a commit (the command failed), it removes its temporary files, so
/// nothing it was given is left behind.
#[derive(Default)]
pub struct Outputs {
    staged: Vec<Staged>,
}

impl Outputs {
    pub fn new() -> Outputs {
        Outputs::default()
    }

    /// Writes `bytes` as the future contents of `path`.
    pub fn add(&mut self, path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), OutputFileError> {
        self.add_with(path, |w| w.write_all(bytes.as_ref()))
    }

    /// Writes the future contents of `path` through `write`, for outputs produced piece
    /// by piece.
    pub fn add_with(
        &mut self,
        path: &Path,
        write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
    ) -> Result<(), OutputFileError> {
        let destination = destination(path)?;
        let io = |source: std::io::Error| OutputFileError::Io {
            path: path.to_path_buf(),
            source,
        };
        if is_special(&destination) {
            let file = std::fs::OpenOptions::new()
                .write(true)
                .open(&destination)
                .map_err(io)?;
            let mut writer = std::io::BufWriter::new(file);
            write(&mut writer).map_err(io)?;
            return writer.flush().map_err(io);
        }
        let (temporary, file) = create_temporary(&destination).map_err(io)?;
        // Registered before writing, so that a failed write removes it on drop.
        self.staged.push(Staged {
            temporary,
            path: destination,
        });
        let mut writer = std::io::BufWriter::new(file);
        write(&mut writer).map_err(io)?;
        let file = writer.into_inner().map_err(|e| io(e.into_error()))?;
        file.sync_all().map_err(io)?;
        Ok(())
    }

    /// Renames every staged output into place, in the order they were added.
    pub fn commit(mut self) -> Result<(), OutputFileError> {
        let staged = std::mem::take(&mut self.staged);
        let mut pending = staged.into_iter();
        while let Some(output) = pending.next() {
            if let Err(source) = std::fs::rename(&output.temporary, &output.path) {
                let _ = std::fs::remove_file(&output.temporary);
                for rest in pending {
                    let _ = std::fs::remove_file(&rest.temporary);
                }
                return Err(OutputFileError::Io {
                    path: output.path,
                    source,
                });
            }
        }
        Ok(())
    }
}

impl Drop for Outputs {
    fn drop(&mut self) {
        for output in &self.staged {
            let _ = std::fs::remove_file(&output.temporary);
        }
    }
}

/// Writes `bytes` to `path` as one [`Outputs`] commit: the file is complete or absent.
pub fn write_atomically(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), OutputFileError> {
    let mut outputs = Outputs::new();
    outputs.add(path, bytes)?;
    outputs.commit()
}

/// The file a write to `path` replaces: `path`, or the file a symbolic link there points
/// to (renaming over the link would replace the link, not the file the user named).
fn destination(path: &Path) -> Result<PathBuf, OutputFileError> {
    match std::fs::symlink_metadata(path) {
        Ok(metadata) if metadata.file_type().is_symlink() => match std::fs::canonicalize(path) {
            Ok(target) => check_destination(path, target),
            // A dangling link: the file it names is created.
            Err(_) => match std::fs::read_link(path) {
                Ok(target) if target.is_absolute() => check_destination(path, target),
                Ok(target) => {
                    let dir = path.parent().unwrap_or(Path::new(""));
                    check_destination(path, dir.join(target))
                }
                Err(source) => Err(OutputFileError::Io {
                    path: path.to_path_buf(),
                    source,
                }),
            },
        },
        _ => check_destination(path, path.to_path_buf()),
    }
}

fn check_destination(named: &Path, destination: PathBuf) -> Result<PathBuf, OutputFileError> {
    if destination.is_dir() {
        return Err(OutputFileError::Directory {
            path: named.to_path_buf(),
        });
    }
    let dir = directory_of(&destination);
    if !dir.is_dir() {
        return Err(OutputFileError::MissingDirectory {
            path: named.to_path_buf(),
        });
    }
    Ok(destination)
}

/// The directory `path` is in ("." for a bare file name).
fn directory_of(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// A new file beside `destination`, named after it and this process so that parallel
/// writers never share one, with the permissions of the file it replaces.
fn create_temporary(destination: &Path) -> std::io::Result<(PathBuf, std::fs::File)> {
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = destination
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    let dir = directory_of(destination);
    loop {
        let k = COUNTER.fetch_add(1, Ordering::Relaxed);
        let temporary = dir.join(format!(".{name}.{}.{k}.tmp", std::process::id()));
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temporary)
        {
            Ok(file) => {
                if let Ok(old) = std::fs::metadata(destination) {
                    let _ = file.set_permissions(old.permissions());
                }
                return Ok((temporary, file));
            }
            // Left by a writer of the same pid that was killed: take the next name.
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("stickslip-files-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn problem(result: Result<Vec<u8>, InputFileError>) -> InputProblem {
        result.unwrap_err().problem
    }

    const SMALL: InputFile = InputFile {
        what: "test file",
        limit: 16,
    };

    #[test]
    fn each_bad_input_has_its_own_problem() {
        let dir = scratch("inputs");
        assert!(matches!(
            problem(SMALL.read(&dir.join("absent"))),
            InputProblem::Missing
        ));
        assert!(matches!(problem(SMALL.read(&dir)), InputProblem::Directory));
        let empty = dir.join("empty");
        std::fs::write(&empty, b"").unwrap();
        assert!(matches!(problem(SMALL.read(&empty)), InputProblem::Empty));
        let large = dir.join("large");
        std::fs::write(&large, [b'x'; 17]).unwrap();
        assert!(matches!(
            problem(SMALL.read(&large)),
            InputProblem::TooLarge {
                size: 17,
                limit: 16
            }
        ));
        let binary = dir.join("binary");
        std::fs::write(&binary, b"ab\xff\xfe").unwrap();
        assert_eq!(SMALL.read(&binary).unwrap(), b"ab\xff\xfe");
        match SMALL.read_text(&binary).unwrap_err().problem {
            InputProblem::NotUtf8 { offset } => assert_eq!(offset, 2),
            other => panic!("{other:?}"),
        }
        let exact = dir.join("exact");
        std::fs::write(&exact, [b'y'; 16]).unwrap();
        assert_eq!(SMALL.read_text(&exact).unwrap(), "y".repeat(16));
    }

    #[cfg(unix)]
    #[test]
    fn devices_are_refused_before_they_are_read() {
        // /dev/zero never ends; /dev/null is a character device too.
        for device in ["/dev/zero", "/dev/null"] {
            let error = WEIGHTS_FILE.read(Path::new(device)).unwrap_err();
            assert!(
                matches!(error.problem, InputProblem::Special("character device")),
                "{device}: {error}"
            );
            assert_eq!(
                error.to_string(),
                format!("weights file {device}: is a character device, not a regular file")
            );
        }
    }

    /// A named pipe stays a pipe and its reader gets the bytes: the writer opens it
    /// instead of renaming a temporary file over it (which would replace the pipe, and
    /// as root `/dev/null`, with a regular file).
    #[cfg(unix)]
    #[test]
    fn a_pipe_is_written_into_not_replaced() {
        use std::os::unix::fs::FileTypeExt;
        let dir = scratch("pipe");
        let pipe = dir.join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&pipe).status();
        if !made.is_ok_and(|s| s.success()) {
            eprintln!("mkfifo unavailable: skipped");
            return;
        }
        // The reader reports through a channel: were the pipe replaced, its open would
        // wait for a writer forever, and the test fails on the type check, not by hanging.
        let (sender, received) = std::sync::mpsc::channel();
        {
            let pipe = pipe.clone();
            std::thread::spawn(move || sender.send(std::fs::read(pipe).unwrap()));
        }
        write_atomically(&pipe, b"t,x\n0,1\n").unwrap();
        assert!(std::fs::metadata(&pipe).unwrap().file_type().is_fifo());
        let bytes = received
            .recv_timeout(std::time::Duration::from_secs(30))
            .unwrap();
        assert_eq!(bytes, b"t,x\n0,1\n");
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(left.len(), 1, "only the pipe: no temporary file left");
    }

    #[test]
    fn a_message_names_the_path_once() {
        let dir = scratch("message");
        let path = dir.join("w.json");
        let message = WEIGHTS_FILE.read(&path).unwrap_err().to_string();
        assert_eq!(
            message,
            format!("weights file {}: no such file", path.display())
        );
        assert_eq!(message.matches("w.json").count(), 1);
    }

    #[test]
    fn an_uncommitted_output_leaves_nothing_and_the_old_file_untouched() {
        let dir = scratch("outputs");
        let old = dir.join("old.txt");
        std::fs::write(&old, b"before").unwrap();
        let new = dir.join("new.txt");
        {
            let mut outputs = Outputs::new();
            outputs.add(&old, b"after").unwrap();
            outputs.add(&new, b"new").unwrap();
            // Dropped: the command failed after staging.
        }
        assert_eq!(std::fs::read(&old).unwrap(), b"before");
        assert!(!new.exists());
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(left.len(), 1, "temporary files left: {left:?}");
    }

    #[test]
    fn a_failed_write_removes_its_temporary_file() {
        let dir = scratch("failed");
        let path = dir.join("out.csv");
        let mut outputs = Outputs::new();
        let error = outputs
            .add_with(&path, |w| {
                w.write_all(b"half")?;
                Err(std::io::Error::other("disk full"))
            })
            .unwrap_err();
        assert_eq!(
            error.to_string(),
            format!("cannot write {}: disk full", path.display())
        );
        drop(outputs);
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    }

    #[test]
    fn committed_outputs_replace_old_files() {
        let dir = scratch("commit");
        let a = dir.join("a");
        std::fs::write(&a, b"old").unwrap();
        let b = dir.join("b");
        let mut outputs = Outputs::new();
        outputs.add(&a, b"A").unwrap();
        outputs.add(&b, b"B").unwrap();
        outputs.commit().unwrap();
        assert_eq!(std::fs::read(&a).unwrap(), b"A");
        assert_eq!(std::fs::read(&b).unwrap(), b"B");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
    }

    #[test]
    fn unwritable_destinations_are_named() {
        let dir = scratch("destinations");
        let in_missing = dir.join("no/such/dir/out.json");
        let error = write_atomically(&in_missing, b"x").unwrap_err();
        assert!(matches!(error, OutputFileError::MissingDirectory { .. }));
        assert_eq!(error.path(), in_missing);
        let error = write_atomically(&dir, b"x").unwrap_err();
        assert!(
            matches!(error, OutputFileError::Directory { .. }),
            "{error}"
        );
    }

    #[cfg(unix)]
    #[test]
    fn a_link_is_written_through() {
        let dir = scratch("link");
        let target = dir.join("target.json");
        std::fs::write(&target, b"old").unwrap();
        let link = dir.join("link.json");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        write_atomically(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
    }
}
