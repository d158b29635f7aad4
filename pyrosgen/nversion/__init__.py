"""A second, independent reading of the node model file (N-version,
DESIGN.md section 7): the model text computed from the YAML without the
front end, compared with the text Coq proved."""
