"""Independent checks of what Coq printed: printer validation, differential tests, ACSL/WP, the certificate (DESIGN.md section 7)."""
