//! Checkpoints: `mcrender render SCENE --checkpoint FILE [--checkpoint-every 60s]` saves the
//! render's state; `mcrender render --resume FILE [-o OUT]` continues it, to the same bytes
//! as a render that was never stopped.
//!
//! File layout (versions 3 and 4), chosen so that a reader needs nothing but this comment:
//!
//! ```text
//! "MCRCKPT\n"                      8 bytes, magic
//! version                          u32 little-endian (4; versions 1 and 2 stored the splat
//!                                  sums as f64 and are refused; version 3 has this layout
//!                                  but splats added to one pixel with weight one, so it is
//!                                  read only when it holds no splats)
//! header length                    u64 little-endian
//! header                           UTF-8 JSON: format, version, binary, fingerprint, cwd,
//!                                  args, output, samples_done, samples_per_pixel, width,
//!                                  height, sections [{name, bytes}]
//! sections                         raw bytes, in the header's order
//! checksum                         32 bytes, SHA-256 of everything before it
//! ```
//!
//! The `film` section holds, per pixel in row-major order, `sum_w`, `sum_wl[3]`,
//! `sum_wl2[3]` (f64) and `count` (u64), then per pixel the splat sums (3 i128, fixed point
//! in units of 2^-64, as `SplatSum` keeps them), all little endian: the accumulators
//! themselves, so the resumed render continues them exactly. A film of filter splatting
//! adds a section `film.filtered` right after it: per pixel the 11 i128 of its
//! `FilteredSums::to_fixed` (sum w, sum w^2, sum w L, sum w^2 L, sum (w L)^2). A
//! JSON header keeps the file self-describing and easy to inspect; raw floats keep it small
//! and exact (no decimal round trip).
//!
//! An integrator with state of its own beyond the film (SPPM's per-pixel radii, photon
//! counts and flux, and its iteration count; MLT's normalisation, chains and splat sums)
//! adds one section `integrator.NAME` after the film, whose bytes only that integrator
//! reads ([`IntegratorState`]; the layouts are
//! `mcrender_core::integrator::sppm::SppmState::to_bytes` and
//! `mcrender_core::integrator::mlt::MltState::to_bytes`). Its film section then holds the
//! image so far (MLT's splat sums thus appear twice: the state is whole without the film
//! section), and its sample count is the integrator's, not the sampler's. A reader refuses
//! sections it does not know, and the fingerprint already ties a checkpoint to its
//! integrator.
//!
//! The fingerprint is a SHA-256 over the binary's version, the scene file's bytes and those
//! of every file it names (includes, meshes, textures; found as quoted strings naming
//! existing files, output images excepted), and the effective camera, film, filter,
//! reconstruction, sampler
//! and integrator settings after the command-line overrides. Thread count, outputs and
//! progress display do not change the image and are not part of it.
//!
//! Writes are atomic: a temporary file in the same directory, renamed over the target when
//! complete, removed on every error path.

use std::collections::HashSet;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{bail, Context, Result};
use clap::{Args, Parser};
use mcrender_core::film::{Film, FilteredSums, PixelStats, SplatSum, FILTERED_SUMS_LEN};
use mcrender_core::scene::SceneDescription;
use serde_json::{json, Value};
use sha2::{Digest, Sha256};

use crate::builtin;
use crate::render_cmd::RenderArgs;

const MAGIC: &[u8; 8] = b"MCRCKPT\n";
const VERSION: u32 = 4;
/// Versions this binary reads (the integrator-state section is optional; version 3 only
/// without splats).
const READS: [u32; 2] = [3, 4];
/// Prefix of the integrator-state section's name.
const STATE_PREFIX: &str = "integrator.";
/// Bytes per pixel in the film section: 7 f64 + 1 u64 + 3 i128.
const FILM_BYTES_PER_PIXEL: usize = 8 * 8 + 3 * 16;
/// Name of the section of a film of filter splatting's sums.
const FILTERED_SECTION: &str = "film.filtered";
/// Bytes per pixel in that section.
const FILTERED_BYTES_PER_PIXEL: usize = 16 * FILTERED_SUMS_LEN;

/// The checkpoint flags of `mcrender render`.
#[derive(Args, Debug, Default, Clone)]
pub struct CheckpointArgs {
    /// Save the render's state to this file every --checkpoint-every and when interrupted
    /// (resume with --resume FILE, or by running the same command again). Default when
    /// interrupted: OUTPUT.ckpt. An existing FILE of another render is refused.
    #[arg(long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    /// Time between checkpoints, e.g. 60s, 500ms, 5m, 1h (default 60s).
    #[arg(long, value_name = "TIME", value_parser = parse_duration)]
    pub checkpoint_every: Option<Duration>,
    /// Continue the render saved in this checkpoint (same scene, settings and outputs unless
    /// -o is given); the image is the same as an uninterrupted render's.
    #[arg(long, value_name = "FILE", conflicts_with_all = [
        "scene", "spp", "resolution", "max_depth", "seed", "sampler", "integrator", "direct",
        "light_samples", "rr", "rr_threshold", "rr_prob", "checkpoint",
    ])]
    pub resume: Option<PathBuf>,
}

/// Parse `60s`, `500ms`, `5m`, `1h` or a number of seconds.
pub fn parse_duration(s: &str) -> Result<Duration, String> {
    let t = s.trim();
    let split = t.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let scale = match unit.trim() {
        "" | "s" => 1.0,
        "ms" => 1e-3,
        "m" | "min" => 60.0,
        "h" => 3600.0,
        _ => return Err(format!("expected a time such as 60s, 500ms, 5m or 1h, found \"{s}\"")),
    };
    let v: f64 = num
        .parse()
        .map_err(|_| format!("expected a time such as 60s, 500ms, 5m or 1h, found \"{s}\""))?;
    let secs = v * scale;
    if !(secs.is_finite() && secs > 0.0 && secs < 1e9) {
        return Err(format!("expected a positive time, found \"{s}\""));
    }
    Ok(Duration::from_secs_f64(secs))
}

/// The state of an integrator with its own driver (SPPM, MLT), saved as the section
/// `integrator.NAME`: bytes only that integrator reads.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct IntegratorState {
    /// The integrator's name (`sppm`, `mlt`).
    pub name: String,
    /// Its serialised state.
    pub bytes: Vec<u8>,
}

/// What a checkpoint holds.
#[derive(Clone, Debug)]
pub struct Checkpoint {
    /// Hex SHA-256 of everything that determines the image.
    pub fingerprint: String,
    /// Working directory of the original command (its relative paths are relative to it).
    pub cwd: PathBuf,
    /// The original `mcrender render` arguments.
    pub args: Vec<String>,
    /// Output image given at a resume (absolute), replacing the original command's.
    pub output: Option<PathBuf>,
    /// Samples per pixel the render is to reach.
    pub samples_per_pixel: u32,
    /// The accumulated film, with `samples_per_pixel()` samples done.
    pub film: Film,
    /// The integrator's own state, for integrators with one.
    pub integrator_state: Option<IntegratorState>,
}

/// How the render was asked for: what a resume re-runs.
#[derive(Clone, Debug)]
pub struct Invocation {
    /// Working directory.
    pub cwd: PathBuf,
    /// `mcrender render` arguments.
    pub args: Vec<String>,
    /// Output override of a resume.
    pub output: Option<PathBuf>,
}

impl Invocation {
    /// This process's own command line.
    pub fn current() -> Result<Self> {
        let mut args = Vec::new();
        for a in std::env::args_os().skip(1) {
            match a.into_string() {
                Ok(s) => args.push(s),
                Err(a) => bail!("checkpoint: argument {a:?} is not valid UTF-8"),
            }
        }
        let args = match args.first().map(String::as_str) {
            Some("render") => args[1..].to_vec(),
            // `mcrender` alone: the built-in default render.
            _ => {
                let (w, h) = builtin::DEFAULT_RESOLUTION;
                vec![
                    "--spp".into(),
                    builtin::DEFAULT_SPP.to_string(),
                    "--resolution".into(),
                    format!("{w}x{h}"),
                    "-o".into(),
                    builtin::DEFAULT_OUTPUT.into(),
                ]
            }
        };
        let cwd = std::env::current_dir().context("cannot read the working directory")?;
        Ok(Self {
            cwd,
            args,
            output: None,
        })
    }
}

/// A resume: the original command's arguments (with this command's -o, --threads, -q and
/// --checkpoint-every on top), and the saved state.
pub struct Resume {
    /// Arguments to render with.
    pub args: RenderArgs,
    /// What to record in later checkpoints.
    pub invocation: Invocation,
    /// The saved state.
    pub checkpoint: Checkpoint,
}

#[derive(Parser)]
#[command(name = "render", no_binary_name = true)]
struct Stored {
    #[command(flatten)]
    args: RenderArgs,
}

/// For `--resume FILE`: read the checkpoint, move to its working directory, and rebuild
/// the original arguments. `None` without `--resume`.
pub fn prepare_resume(args: &RenderArgs) -> Result<Option<Resume>> {
    let Some(path) = &args.checkpointing.resume else {
        return Ok(None);
    };
    let abs = |p: &Path| std::path::absolute(p).with_context(|| format!("cannot resolve \"{}\"", p.display()));
    let path = abs(path)?;
    let output = args.output.as_deref().map(abs).transpose()?;
    let variance = args.variance_output.as_deref().map(abs).transpose()?;
    let ck = read(&path)?;
    std::env::set_current_dir(&ck.cwd).with_context(|| {
        format!(
            "checkpoint \"{}\": cannot enter the original working directory \"{}\"",
            path.display(),
            ck.cwd.display()
        )
    })?;
    let stored = Stored::try_parse_from(&ck.args).map_err(|e| {
        anyhow::anyhow!(
            "checkpoint \"{}\": its command line no longer parses: {}",
            path.display(),
            e.kind()
        )
    })?;
    let mut new = stored.args;
    let output = output.or_else(|| ck.output.clone());
    if let Some(o) = &output {
        new.output = Some(o.clone());
    }
    if variance.is_some() {
        new.variance_output = variance;
    }
    if args.scene.threads.is_some() {
        new.scene.threads = args.scene.threads;
    }
    new.quiet |= args.quiet;
    if args.checkpointing.checkpoint_every.is_some() {
        new.checkpointing.checkpoint_every = args.checkpointing.checkpoint_every;
    }
    new.checkpointing.checkpoint = Some(path);
    new.checkpointing.resume = None;
    let invocation = Invocation {
        cwd: ck.cwd.clone(),
        args: ck.args.clone(),
        output,
    };
    Ok(Some(Resume {
        args: new,
        invocation,
        checkpoint: ck,
    }))
}

/// The fingerprint of a render: see the module documentation. `scene` is the scene file
/// (`None`: the built-in one); `outputs` are files the render writes, never hashed.
pub fn fingerprint(scene: Option<&Path>, desc: &SceneDescription, outputs: &[&Path]) -> Result<String> {
    let mut h = Sha256::new();
    let mut put = |bytes: &[u8]| {
        h.update((bytes.len() as u64).to_le_bytes());
        h.update(bytes);
    };
    put(b"mcrender checkpoint fingerprint 1");
    put(env!("CARGO_PKG_VERSION").as_bytes());
    match scene {
        None => put(builtin::SOURCE.as_bytes()),
        Some(path) => {
            let skip: HashSet<PathBuf> = outputs.iter().filter_map(|p| std::fs::canonicalize(p).ok()).collect();
            let mut seen = HashSet::new();
            let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
            hash_file_tree(path, &base, &skip, &mut seen, 0, &mut put)?;
        }
    }
    put(format!(
        "{:?}\n{:?}\n{:?}\n{:?}\n{:?}\n{:?}",
        desc.camera, desc.film, desc.filter, desc.reconstruction, desc.sampler, desc.integrator
    )
    .as_bytes());
    Ok(hex(&h.finalize()))
}

/// Hash `path` and, for scene files, every existing file named by a quoted string in it
/// (relative to the main scene's directory or to the file's own).
fn hash_file_tree(
    path: &Path,
    base: &Path,
    skip: &HashSet<PathBuf>,
    seen: &mut HashSet<PathBuf>,
    depth: u32,
    put: &mut impl FnMut(&[u8]),
) -> Result<()> {
    let canonical = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    if skip.contains(&canonical) || !seen.insert(canonical) {
        return Ok(());
    }
    let bytes = std::fs::read(path).with_context(|| format!("cannot read \"{}\"", path.display()))?;
    put(path.file_name().map_or(&[][..], |n| n.as_encoded_bytes()));
    put(&bytes);
    let is_scene = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("pbrt"));
    if !is_scene || depth > 16 {
        return Ok(());
    }
    let text = String::from_utf8_lossy(&bytes);
    let own_dir = path.parent().unwrap_or(Path::new("."));
    for name in text.split('"').skip(1).step_by(2) {
        if name.is_empty() || name.len() > 4096 || name.contains('\n') {
            continue;
        }
        for dir in [base, own_dir] {
            let candidate = dir.join(name);
            if candidate.is_file() {
                hash_file_tree(&candidate, base, skip, seen, depth + 1, put)?;
                break;
            }
        }
    }
    Ok(())
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Write a checkpoint atomically, with the integrator's own `state` if it has one.
pub fn write(
    path: &Path,
    fingerprint: &str,
    invocation: &Invocation,
    spp: u32,
    film: &Film,
    state: Option<&IntegratorState>,
) -> Result<()> {
    let what = || format!("cannot write checkpoint \"{}\"", path.display());
    let n = film.pixels().len();
    let mut sections = vec![json!({"name": "film", "bytes": n * FILM_BYTES_PER_PIXEL})];
    if film.filtered_sums().is_some() {
        sections.push(json!({"name": FILTERED_SECTION, "bytes": n * FILTERED_BYTES_PER_PIXEL}));
    }
    sections.extend(state.map(|s| json!({"name": format!("{STATE_PREFIX}{}", s.name), "bytes": s.bytes.len()})));
    let header = json!({
        "format": "mcrender checkpoint",
        "version": VERSION,
        "binary": concat!("mcrender ", env!("CARGO_PKG_VERSION")),
        "fingerprint": fingerprint,
        "cwd": invocation.cwd.to_string_lossy(),
        "args": invocation.args,
        "output": invocation.output.as_ref().map(|p| p.to_string_lossy()),
        "samples_done": film.samples_per_pixel(),
        "samples_per_pixel": spp,
        "width": film.width(),
        "height": film.height(),
        "sections": sections,
    });
    let header = serde_json::to_vec(&header).with_context(what)?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .map_or_else(|| "checkpoint".into(), |n| n.to_string_lossy().into_owned());
    // Dropped (and so removed) on every early return.
    let tmp = tempfile::Builder::new()
        .prefix(&format!(".{name}.tmp-"))
        .tempfile_in(dir)
        .with_context(what)?;
    {
        let mut out = HashingWriter {
            inner: std::io::BufWriter::new(tmp.as_file()),
            hash: Sha256::new(),
        };
        out.write_all(MAGIC)?;
        out.write_all(&VERSION.to_le_bytes())?;
        out.write_all(&(header.len() as u64).to_le_bytes())?;
        out.write_all(&header)?;
        for p in film.pixels() {
            let v = [
                p.sum_w,
                p.sum_wl[0],
                p.sum_wl[1],
                p.sum_wl[2],
                p.sum_wl2[0],
                p.sum_wl2[1],
                p.sum_wl2[2],
            ];
            for x in v {
                out.write_all(&x.to_le_bytes())?;
            }
            out.write_all(&p.count.to_le_bytes())?;
        }
        for s in film.splat_sums() {
            for x in s.to_fixed() {
                out.write_all(&x.to_le_bytes())?;
            }
        }
        for f in film.filtered_sums().unwrap_or_default() {
            for x in f.to_fixed() {
                out.write_all(&x.to_le_bytes())?;
            }
        }
        if let Some(s) = state {
            out.write_all(&s.bytes)?;
        }
        let digest = out.hash.finalize_reset();
        out.inner.write_all(&digest).with_context(what)?;
        out.inner.flush().with_context(what)?;
    }
    tmp.as_file().sync_all().with_context(what)?;
    tmp.persist(path).map_err(|e| e.error).with_context(what)?;
    Ok(())
}

/// Writes through and hashes what it wrote.
struct HashingWriter<W> {
    inner: W,
    hash: Sha256,
}

impl<W: Write> Write for HashingWriter<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.hash.update(&buf[..n]);
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

/// Read and validate a checkpoint (magic, version, checksum, sizes); every failure is one
/// line naming the file.
pub fn read(path: &Path) -> Result<Checkpoint> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read checkpoint \"{}\"", path.display()))?;
    parse(&bytes).map_err(|why| anyhow::anyhow!("checkpoint \"{}\": {why}", path.display()))
}

fn parse(bytes: &[u8]) -> Result<Checkpoint, String> {
    if bytes.len() < MAGIC.len() + 12 + 32 || &bytes[..8] != MAGIC {
        return Err(if bytes.starts_with(MAGIC) {
            "truncated (shorter than a header)".into()
        } else {
            "not an mcrender checkpoint".into()
        });
    }
    let (body, sum) = bytes.split_at(bytes.len() - 32);
    let version = u32::from_le_bytes(body[8..12].try_into().expect("4 bytes"));
    if !READS.contains(&version) {
        return Err(format!(
            "format version {version}, this mcrender reads version {VERSION} (earlier versions stored the splat sums as f64)"
        ));
    }
    if Sha256::digest(body).as_slice() != sum {
        return Err("truncated or damaged (checksum mismatch)".into());
    }
    let header_len = u64::from_le_bytes(body[12..20].try_into().expect("8 bytes"));
    let header_end = usize::try_from(header_len)
        .ok()
        .and_then(|l| l.checked_add(20))
        .filter(|&e| e <= body.len())
        .ok_or("header longer than the file")?;
    let header: Value = serde_json::from_slice(&body[20..header_end]).map_err(|e| format!("bad header: {e}"))?;
    let field = |k: &str| header.get(k).ok_or_else(|| format!("header has no \"{k}\""));
    let uint = |k: &str| {
        field(k)?
            .as_u64()
            .ok_or_else(|| format!("header \"{k}\" is not a count"))
    };
    let text = |k: &str| {
        field(k)?
            .as_str()
            .map(str::to_owned)
            .ok_or_else(|| format!("header \"{k}\" is not text"))
    };
    let (width, height) = (uint("width")?, uint("height")?);
    let to_u32 = |v: u64, k: &str| u32::try_from(v).map_err(|_| format!("header \"{k}\" too large"));
    let (width, height) = (to_u32(width, "width")?, to_u32(height, "height")?);
    let samples_per_pixel = to_u32(uint("samples_per_pixel")?, "samples_per_pixel")?;
    let samples_done = uint("samples_done")?;
    let args = field("args")?
        .as_array()
        .and_then(|a| {
            a.iter()
                .map(|v| v.as_str().map(str::to_owned))
                .collect::<Option<Vec<_>>>()
        })
        .ok_or("header \"args\" is not a list of text")?;
    let output = match field("output")? {
        Value::Null => None,
        Value::String(s) => Some(PathBuf::from(s)),
        _ => return Err("header \"output\" is not text".into()),
    };
    let sections = field("sections")?
        .as_array()
        .ok_or("header \"sections\" is not a list")?;
    let mut at = header_end;
    let mut film = None;
    let mut filtered = None;
    let mut integrator_state = None;
    for s in sections {
        let name = s
            .get("name")
            .and_then(Value::as_str)
            .ok_or("a section without a name")?;
        let len = s
            .get("bytes")
            .and_then(Value::as_u64)
            .and_then(|l| usize::try_from(l).ok())
            .ok_or("a section without a size")?;
        let end = at
            .checked_add(len)
            .filter(|&e| e <= body.len())
            .ok_or("truncated (section past the end)")?;
        let data = &body[at..end];
        at = end;
        match name {
            "film" => film = Some(read_film(data, width, height, samples_done)?),
            FILTERED_SECTION => filtered = Some(read_filtered(data)?),
            state if version >= 2 && state.starts_with(STATE_PREFIX) => {
                if integrator_state.is_some() {
                    return Err("two integrator sections".into());
                }
                integrator_state = Some(IntegratorState {
                    name: state[STATE_PREFIX.len()..].to_owned(),
                    bytes: data.to_vec(),
                });
            }
            other => return Err(format!("unknown section \"{other}\" (written by a newer mcrender?)")),
        }
    }
    if at != body.len() {
        return Err("bytes after the last section".into());
    }
    let mut film = film.ok_or("no film section")?;
    if let Some(f) = filtered {
        film = film
            .with_filtered_sums(f)
            .ok_or("filtered sums section of the wrong size")?;
    }
    if version == 3 && film.splat_sums().iter().any(|s| !s.is_zero()) {
        return Err(
            "format version 3 with splats, which that version added to one pixel; this mcrender spreads them with the pixel filter (render again)"
                .into(),
        );
    }
    Ok(Checkpoint {
        fingerprint: text("fingerprint")?,
        cwd: PathBuf::from(text("cwd")?),
        args,
        output,
        samples_per_pixel,
        film,
        integrator_state,
    })
}

fn read_film(data: &[u8], width: u32, height: u32, spp: u64) -> Result<Film, String> {
    let n = (width as usize)
        .checked_mul(height as usize)
        .filter(|n| n.checked_mul(FILM_BYTES_PER_PIXEL) == Some(data.len()))
        .ok_or("film section of the wrong size")?;
    let word = |i: usize| u64::from_le_bytes(data[8 * i..8 * i + 8].try_into().expect("8 bytes"));
    let float = |i: usize| f64::from_bits(word(i));
    let pixels = (0..n)
        .map(|p| {
            let b = p * 8;
            PixelStats {
                sum_w: float(b),
                sum_wl: [float(b + 1), float(b + 2), float(b + 3)],
                sum_wl2: [float(b + 4), float(b + 5), float(b + 6)],
                count: word(b + 7),
            }
        })
        .collect();
    let splats_at = 64 * n;
    let fixed = |i: usize| {
        let at = splats_at + 16 * i;
        i128::from_le_bytes(data[at..at + 16].try_into().expect("16 bytes"))
    };
    let splats = (0..n)
        .map(|p| SplatSum::from_fixed([fixed(3 * p), fixed(3 * p + 1), fixed(3 * p + 2)]))
        .collect();
    Film::from_parts(width, height, pixels, splats, spp).ok_or_else(|| "film of the wrong size".into())
}

/// The filter-splatting sums of a `film.filtered` section.
fn read_filtered(data: &[u8]) -> Result<Vec<FilteredSums>, String> {
    if !data.len().is_multiple_of(FILTERED_BYTES_PER_PIXEL) {
        return Err("filtered sums section of the wrong size".into());
    }
    Ok(data
        .chunks_exact(FILTERED_BYTES_PER_PIXEL)
        .map(|p| {
            FilteredSums::from_fixed(std::array::from_fn(|k| {
                i128::from_le_bytes(p[16 * k..16 * k + 16].try_into().expect("16 bytes"))
            }))
        })
        .collect())
}

/// Refuse a checkpoint made for another scene, other settings or another binary.
pub fn check_fingerprint(path: &Path, ck: &Checkpoint, fingerprint: &str, desc: &SceneDescription) -> Result<()> {
    if ck.fingerprint != fingerprint {
        bail!(
            "checkpoint \"{}\" was made for another scene, other settings or another mcrender version \
             (fingerprint {}..., now {}...); nothing was written",
            path.display(),
            &ck.fingerprint[..ck.fingerprint.len().min(12)],
            &fingerprint[..12]
        );
    }
    let (w, h) = (desc.film.width, desc.film.height);
    if (ck.film.width(), ck.film.height()) != (w, h) || ck.samples_per_pixel != desc.sampler.samples_per_pixel {
        bail!("checkpoint \"{}\": its film does not match the scene's", path.display());
    }
    // An integrator with its own state counts its own progress (SPPM iterations, MLT
    // mutations) and checks it itself.
    if ck.integrator_state.is_none() && ck.film.samples_per_pixel() > u64::from(ck.samples_per_pixel) {
        bail!("checkpoint \"{}\": more samples done than asked for", path.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use mcrender_core::color::Rgb;

    fn film() -> Film {
        let mut f = Film::new(3, 2);
        f.pixel_mut(1, 1).add(Rgb::new(0.1, 0.2, 0.3), 0.7);
        f.pixel_mut(2, 0).add(Rgb::splat(1e-30), 1.0);
        f.add_samples_per_pixel(1);
        // The default Gaussian: the splat reaches several pixels.
        f.add_splat(
            &mcrender_core::film::Splat {
                p_film: mcrender_core::math::Vec2::new(0.5, 1.5),
                l: Rgb::splat(0.25),
            },
            &mcrender_core::film::Filter::new(&mcrender_core::scene::FilterDesc::default()),
        );
        f
    }

    fn invocation() -> Invocation {
        Invocation {
            cwd: PathBuf::from("/tmp"),
            args: vec!["scene.pbrt".into(), "--spp".into(), "4".into()],
            output: None,
        }
    }

    #[test]
    fn round_trip_is_exact_and_damage_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.ckpt");
        write(&path, "ab12", &invocation(), 4, &film(), None).unwrap();
        let ck = read(&path).unwrap();
        assert_eq!(ck.film, film());
        assert_eq!(ck.integrator_state, None);
        assert_eq!((ck.fingerprint.as_str(), ck.samples_per_pixel), ("ab12", 4));
        assert_eq!(ck.args, invocation().args);
        // Only the checkpoint is left: no temporary file.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        let bytes = std::fs::read(&path).unwrap();
        for cut in [0, 10, 30, bytes.len() / 2, bytes.len() - 1] {
            assert!(parse(&bytes[..cut]).is_err(), "cut at {cut}");
        }
        let mut flipped = bytes.clone();
        flipped[bytes.len() / 2] ^= 1;
        assert!(parse(&flipped).unwrap_err().contains("checksum"));
    }

    #[test]
    fn a_film_of_filter_splatting_round_trips_with_its_sums() {
        let mut f = Film::for_filter_splatting(3, 2);
        let tent = mcrender_core::film::Filter::new(&mcrender_core::scene::FilterDesc::Triangle {
            radius: mcrender_core::math::Vec2::splat(1.0),
        });
        let sample = |x: f32, y: f32, v: f32| mcrender_core::film::Splat {
            p_film: mcrender_core::math::Vec2::new(x, y),
            l: Rgb::new(v, 2.0 * v, 0.5),
        };
        let whole = mcrender_core::film::Footprint {
            x0: 0,
            x1: 3,
            y0: 0,
            y1: 2,
        };
        for s in 0..3 {
            let v = 0.1 + s as f32;
            assert_eq!(
                f.add_filtered(&[sample(0.3, 0.6, v), sample(1.7, 1.2, 3.0 * v)], &tent, whole),
                0
            );
            f.add_samples_per_pixel(1);
        }
        assert!(f.filtered_sums().unwrap().iter().any(|s| !s.is_zero()));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.ckpt");
        write(&path, "ab12", &invocation(), 4, &f, None).unwrap();
        let ck = read(&path).unwrap();
        assert_eq!(ck.film, f);
        assert_eq!(ck.film.variance_image(), f.variance_image());
        // The section is known by its name; a damaged size is refused.
        let bytes = std::fs::read(&path).unwrap();
        let text = String::from_utf8_lossy(&bytes);
        assert!(text.contains("\"film.filtered\""));
        assert!(read_filtered(&[0u8; 17]).is_err());
    }

    #[test]
    fn an_integrator_state_round_trips_and_other_versions_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.ckpt");
        let state = IntegratorState {
            name: "sppm".into(),
            bytes: (0..=255).collect(),
        };
        write(&path, "ab12", &invocation(), 4, &film(), Some(&state)).unwrap();
        let ck = read(&path).unwrap();
        assert_eq!((ck.film, ck.integrator_state), (film(), Some(state)));
        let bytes = std::fs::read(&path).unwrap();
        assert!(parse(&bytes[..bytes.len() - 40]).is_err());

        // Without the integrator section; then the same bytes marked as other versions.
        write(&path, "ab12", &invocation(), 4, &film(), None).unwrap();
        let mut file = std::fs::read(&path).unwrap();
        assert_eq!(parse(&file).unwrap().film, film());
        file.truncate(file.len() - 32);
        let signed = |file: &[u8], version: u32| {
            let mut f = file.to_vec();
            f[8..12].copy_from_slice(&version.to_le_bytes());
            let sum = Sha256::digest(&f);
            f.extend_from_slice(&sum);
            f
        };
        for version in [2u32, 5] {
            let err = parse(&signed(&file, version)).unwrap_err();
            assert!(err.contains(&format!("version {version}")), "{err}");
        }
        // Version 3 added splats to one pixel: refused with splats, read without.
        let err = parse(&signed(&file, 3)).unwrap_err();
        assert!(err.contains("version 3 with splats"), "{err}");
        let f = film();
        let no_splats = Film::from_parts(
            f.width(),
            f.height(),
            f.pixels().to_vec(),
            vec![SplatSum::ZERO; f.pixels().len()],
            f.samples_per_pixel(),
        )
        .unwrap();
        write(&path, "ab12", &invocation(), 4, &no_splats, None).unwrap();
        let mut file = std::fs::read(&path).unwrap();
        file.truncate(file.len() - 32);
        assert_eq!(parse(&signed(&file, 3)).unwrap().film, no_splats);
    }

    #[test]
    fn durations_parse() {
        assert_eq!(parse_duration("60s"), Ok(Duration::from_secs(60)));
        assert_eq!(parse_duration("500ms"), Ok(Duration::from_millis(500)));
        assert_eq!(parse_duration("2m"), Ok(Duration::from_secs(120)));
        assert_eq!(parse_duration("1.5"), Ok(Duration::from_millis(1500)));
        assert!(parse_duration("0s").is_err());
        assert!(parse_duration("soon").is_err());
    }
}
