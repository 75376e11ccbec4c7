//! The 2010 protocol (in progress).
