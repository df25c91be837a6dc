//! Drawings (SVG, and PNG through `resvg`) and progress bars for the command line.
//!
//! * [`svg`]: a small SVG builder — axes with ticks and labels, clipped polylines, shaded
//!   bands, circles, text, legends, multi-panel layouts.
//! * [`drawings`]: the drawings of the commands — joint curves and tool path (`reach move`,
//!   `reach plan`, `reach path`), seed 000's detour (`reach avoid`), C-space sections
//!   (`reach cspace`), a top view of points visited in order (`reach tasks`).
//! * [`write_svg`] / [`write_png`]: write a drawing to a file; PNG text uses the system fonts,
//!   and when none are installed a note goes to stderr and the PNG is drawn without text.
//! * [`progress`]: a progress bar on stderr, only when stdout and stderr are terminals.
//!
//! The library crate stays free of drawing and terminal dependencies.

pub mod drawings;
pub mod progress;
pub mod svg;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use clap::Args;

pub use svg::Svg;

use crate::error::CliError;

/// The drawing options shared by `reach move`, `reach plan`, `reach avoid` and `reach path`.
#[derive(Debug, Clone, Default, Args)]
pub struct DrawArgs {
    /// Also draw the result as SVG into FILE (`reach plan`: into the directory FILE, one
    /// file per motion).
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,

    /// Also draw the result as PNG into FILE (`reach plan`: a directory, as --svg).
    #[arg(long, value_name = "FILE")]
    pub png: Option<PathBuf>,

    /// Width of the PNG in pixels (default: the drawing's own width; the height keeps the
    /// aspect ratio).
    #[arg(long, value_name = "PX", requires = "png")]
    pub png_width: Option<u32>,
}

impl DrawArgs {
    /// Whether any drawing was asked for.
    #[must_use]
    pub fn any(&self) -> bool {
        self.svg.is_some() || self.png.is_some()
    }

    /// Checks the output paths before any work is done: their parent directories must exist.
    ///
    /// # Errors
    /// [`CliError::BadInput`] naming the option and the path.
    pub fn check_files(&self) -> Result<(), CliError> {
        check_parent("--svg", self.svg.as_deref())?;
        check_parent("--png", self.png.as_deref())?;
        check_png_width(self.png_width)
    }

    /// Writes `drawing` to the requested files.
    ///
    /// # Errors
    /// [`CliError::BadInput`] when a file cannot be written; [`CliError::Internal`] when the
    /// rasteriser rejects the drawing.
    pub fn write(&self, drawing: &Svg) -> Result<(), CliError> {
        if let Some(path) = &self.svg {
            write_svg("--svg", path, drawing)?;
        }
        if let Some(path) = &self.png {
            write_png("--png", path, drawing, self.png_width)?;
        }
        Ok(())
    }
}

fn check_png_width(width: Option<u32>) -> Result<(), CliError> {
    match width {
        Some(w) if !(16..=20_000).contains(&w) => {
            Err(CliError::bad_input(format!("--png-width must be between 16 and 20000 pixels, got {w}")))
        }
        _ => Ok(()),
    }
}

/// Checks that the directory a file is to be written into exists.
///
/// # Errors
/// [`CliError::BadInput`] naming `option` and the path.
pub fn check_parent(option: &str, path: Option<&Path>) -> Result<(), CliError> {
    let Some(path) = path else { return Ok(()) };
    if path.as_os_str().is_empty() || path.is_dir() {
        return Err(CliError::bad_input(format!("{option} {}: expected a file name", path.display())));
    }
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return Err(CliError::bad_input(format!(
            "{option} {}: directory {} does not exist",
            path.display(),
            parent.display()
        )));
    }
    Ok(())
}

/// Checks (or creates) an output directory for a series of drawings.
///
/// # Errors
/// [`CliError::BadInput`] when the path exists and is not a directory, or cannot be created.
pub fn ensure_dir(option: &str, dir: &Path) -> Result<(), CliError> {
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::bad_input(format!("{option} {}: not a directory", dir.display())));
    }
    std::fs::create_dir_all(dir).map_err(|e| CliError::bad_input(format!("{option} {}: {e}", dir.display())))
}

/// Writes the drawing as an SVG file.
///
/// # Errors
/// [`CliError::BadInput`] naming `option` and the path when the file cannot be written.
pub fn write_svg(option: &str, path: &Path, drawing: &Svg) -> Result<(), CliError> {
    crate::output::write_file(option, path, drawing.finish())
}

/// The system fonts, loaded once; a note goes to stderr when none are found (the PNG is then
/// drawn without text).
fn fonts() -> std::sync::Arc<resvg::usvg::fontdb::Database> {
    static FONTS: OnceLock<std::sync::Arc<resvg::usvg::fontdb::Database>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = resvg::usvg::fontdb::Database::new();
            db.load_system_fonts();
            if db.is_empty() {
                eprintln!("note: no system fonts found; PNG drawings are written without text");
            }
            std::sync::Arc::new(db)
        })
        .clone()
}

/// Rasterises the drawing with `resvg` and writes a PNG, `width` pixels wide (default: the
/// drawing's width), the height keeping the aspect ratio.
///
/// # Errors
/// [`CliError::BadInput`] for a bad width or an unwritable file; [`CliError::Internal`] when
/// the drawing cannot be parsed or encoded (a bug).
pub fn write_png(option: &str, path: &Path, drawing: &Svg, width: Option<u32>) -> Result<(), CliError> {
    check_png_width(width)?;
    let png = render_png(drawing, width)?;
    crate::output::write_file(option, path, png)
}

/// The PNG bytes of a drawing (see [`write_png`]).
///
/// # Errors
/// [`CliError::Internal`] when the drawing cannot be parsed, is too large, or cannot be encoded.
pub fn render_png(drawing: &Svg, width: Option<u32>) -> Result<Vec<u8>, CliError> {
    use resvg::{tiny_skia, usvg};
    let options = usvg::Options { fontdb: fonts(), ..usvg::Options::default() };
    let tree = usvg::Tree::from_str(&drawing.finish(), &options)
        .map_err(|e| CliError::internal(format!("drawing could not be parsed: {e}")))?;
    let size = tree.size();
    let w = width.unwrap_or(size.width().round() as u32).max(1);
    let scale = w as f32 / size.width();
    let h = ((size.height() * scale).round() as u32).max(1);
    let mut pixmap = tiny_skia::Pixmap::new(w, h)
        .ok_or_else(|| CliError::bad_input(format!("PNG of {w} x {h} pixels is too large")))?;
    resvg::render(&tree, tiny_skia::Transform::from_scale(scale, scale), &mut pixmap.as_mut());
    pixmap.encode_png().map_err(|e| CliError::internal(format!("PNG encoding failed: {e}")))
}

/// A file name piece for a number: `30` → `30`, `-7.5` → `m7p5`.
#[must_use]
pub fn file_number(v: f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    let r = if r == 0.0 { 0.0 } else { r };
    format!("{r}").replace('-', "m").replace('.', "p")
}
