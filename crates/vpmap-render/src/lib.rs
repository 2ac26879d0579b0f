//! vpmap-render (in progress)
