#!/usr/bin/env bash
# Build the user's manual (mdBook over docs/, docs/SUMMARY.md) into target/book, with the Rust
# API (cargo doc --no-deps --lib) under target/book/rust, and check every internal link and
# anchor of the result (scripts/check-links.py; no network). The Python reference page,
# docs/manual/python-api.md, is generated from the package's stubs and docstrings by
# scripts/pyref.py; this script only checks that the committed page is up to date.
# mdBook is installed (pinned version, ~6 min of compiling on 2 cores) only when missing.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
MDBOOK_VERSION=0.4.52

if ! command -v mdbook >/dev/null || [ "$(mdbook --version)" != "mdbook v$MDBOOK_VERSION" ]; then
  echo "== cargo install mdbook $MDBOOK_VERSION (search only: no serve/watch)"
  cargo install mdbook --version "$MDBOOK_VERSION" --locked --no-default-features --features search
fi

echo "== Python reference up to date (scripts/pyref.py --check)"
python3 scripts/pyref.py --check

echo "== docs/SUMMARY.md from docs/SUMMARY.in.md (scripts/book-summary.py)"
python3 scripts/book-summary.py
echo "== mdbook build docs -> target/book"
rm -rf target/book
mdbook build docs

echo "== cargo doc --no-deps --lib -> target/book/rust"
cargo doc --no-deps --lib -p dpdnl --quiet
DOC="${CARGO_TARGET_DIR:-$ROOT/target}/doc"
mkdir -p target/book/rust
cp -r "$DOC"/. target/book/rust/

echo "== link check (internal links and anchors, no network)"
python3 scripts/check-links.py target/book
echo "== manual: target/book/index.html"
