"""The doors a user comes in by: the ``transplanter`` command (:mod:`~transplanter.app.cli`: the parser
and ``main``; each command's work in a module named after it — :mod:`~transplanter.app.build`,
:mod:`~transplanter.app.analyse`, :mod:`~transplanter.app.optimise`, :mod:`~transplanter.app.check`,
:mod:`~transplanter.app.pair` — with the option types in :mod:`~transplanter.app.options` and the
proof figures in words in :mod:`~transplanter.app.proof_lines`), the pytest plugin that makes every
part a test (:mod:`~transplanter.app.pytest_plugin`) and helpers for tests of exported files
(:mod:`~transplanter.app.testing`, also importable as ``transplanter.testing``).

May import
    everything: this is the top layer.
"""
