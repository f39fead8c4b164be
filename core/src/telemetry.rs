//! Telemetry record decimation and drop counting for the firmware's defmt log. STUB.
