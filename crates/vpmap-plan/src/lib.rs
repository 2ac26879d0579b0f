//! vpmap-plan (in progress)
