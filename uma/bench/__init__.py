"""Benchmarks behind `uma bench NAME`; each compares methods side by side in one process.

Modules import their heavy dependencies inside functions; the CLI wrappers live in
`uma/cli/bench_*.py`.
"""
