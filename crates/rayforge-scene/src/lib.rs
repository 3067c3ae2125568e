//! The YAML scene format.
