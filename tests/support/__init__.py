"""Helpers shared by the tests, one module per test folder they serve:
``frontend`` (model corpus, ``# expect:`` lines), ``generate`` (Coq
helpers, stand-in libraries, golden files), ``printer`` (the Coq printer),
``validation``, ``diagram``, ``docs``, ``ros`` (private masters, nodes and
drivers, recorded by PID) and ``expect`` (what a node must publish).

Importable as ``support.<module>``: ``tests/conftest.py`` puts ``tests/``
on ``sys.path``."""
