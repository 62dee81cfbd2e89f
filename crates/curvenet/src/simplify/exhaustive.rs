//! Exhaustive search (placeholder replaced below).
