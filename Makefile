# Two entry points for a fresh Debian machine (see README):
#   make demo   install everything, then run the main job on the embedded default
#   make test   install everything, then run the test suite
#   make docs   build the documentation site into site/ (offline, warnings as errors)
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
APT_PACKAGES := libusb-1.0-0 libgomp1 libegl1 libegl-mesa0 libgl1-mesa-dri libopengl0 libosmesa6 chromium chromium-driver
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

.PHONY: demo test install system-deps lint docs

demo: install
	$(VENV)/bin/simgrasp demo

test: install
	$(VENV)/bin/python -m pytest -n 2 --dist loadgroup

docs: install
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict --site-dir site

lint: install
	$(VENV)/bin/ruff check . && $(VENV)/bin/ruff format --check . && $(VENV)/bin/mypy

install: system-deps $(VENV)/.installed

system-deps:
	@missing=$$(for p in $(APT_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing system packages:" $$missing; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing python3-venv; \
	fi

$(VENV)/.installed: pyproject.toml
	[ -x $(VENV)/bin/python ] || $(PYTHON) -m venv $(VENV)
	$(VENV)/bin/python -m pip install -q --upgrade pip
	$(VENV)/bin/python -m pip install -q -e '.[dev,ray,docs]'
	touch $@
