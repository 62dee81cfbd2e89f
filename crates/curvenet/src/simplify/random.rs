//! Random search (placeholder replaced below).
