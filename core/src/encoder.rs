//! Quadrature counter extension: 16-bit hardware counters to 32-bit positions. STUB.
