//! errata_cases
