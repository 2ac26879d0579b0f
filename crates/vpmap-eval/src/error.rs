//! The crate's one error type.

use std::fmt;

/// What can go wrong while measuring, reporting or writing results.
///
/// Messages carry the offending values and paths; a [`EvalError::Context`] chain reads, through
/// `{err:#}` in `anyhow`, as `outer: inner: cause`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EvalError {
    /// Bad input: an option out of range, a malformed file, a map without queries.
    #[error("{0}")]
    Invalid(String),
    /// A file or folder could not be read, listed or written (wrapped in
    /// [`EvalError::Context`] naming the path).
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// A map or scenario file could not be read or planned on.
    #[error(transparent)]
    Plan(#[from] vpmap_plan::PlanError),
    /// A floor map or a truth could not be rasterised into a grid.
    #[error(transparent)]
    Raster(#[from] vpmap_raster::RasterError),
    /// A scene could not be synthesised or built into a map.
    #[error(transparent)]
    Metrology(#[from] vpmap_metrology::MetrologyError),
    /// A plot could not be rendered to PNG.
    #[error(transparent)]
    Render(#[from] vpmap_render::RenderError),
    /// A report could not be serialised to JSON.
    #[error(transparent)]
    Json(#[from] serde_json::Error),
    /// An error with what was being done when it happened.
    #[error("{context}")]
    Context {
        /// What was being done ("maze512-1-0: query 3").
        context: String,
        /// The error itself.
        #[source]
        source: Box<EvalError>,
    },
}

/// `Result` with [`EvalError`].
pub type Result<T, E = EvalError> = std::result::Result<T, E>;

/// Adds what was being done to an error, as `anyhow::Context` does.
pub(crate) trait ResultExt<T> {
    /// Wrap the error in [`EvalError::Context`] with the text `f` makes.
    fn with_context<C: fmt::Display, F: FnOnce() -> C>(self, f: F) -> Result<T>;
    /// Wrap the error in [`EvalError::Context`] with `context`.
    fn context<C: fmt::Display>(self, context: C) -> Result<T>;
}

impl<T, E: Into<EvalError>> ResultExt<T> for std::result::Result<T, E> {
    fn with_context<C: fmt::Display, F: FnOnce() -> C>(self, f: F) -> Result<T> {
        self.map_err(|e| EvalError::Context {
            context: f().to_string(),
            source: Box::new(e.into()),
        })
    }

    fn context<C: fmt::Display>(self, context: C) -> Result<T> {
        self.with_context(|| context)
    }
}

/// Return an [`EvalError::Invalid`] with a formatted message.
macro_rules! bail {
    ($($arg:tt)*) => {
        return Err($crate::error::EvalError::Invalid(format!($($arg)*)))
    };
}
pub(crate) use bail;
