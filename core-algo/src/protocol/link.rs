//! The reliable link (in progress).
