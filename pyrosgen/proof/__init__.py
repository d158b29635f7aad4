"""The proof layer: the model as Coq terms, the Coq driver (coqc, coqchk, extraction) and the AST dump."""
