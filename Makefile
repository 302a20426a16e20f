# Set-up and main entry points. Every target creates or reuses the local virtualenv in .venv.
#   make demo   core install only (no torch): the baseline evaluation on the default suite
#   make test   adds the rl, test and docs extras (stable-baselines3, a CPU build of torch, Sphinx) and runs the tests
#   make docs   the documentation site (Sphinx, MyST, furo) with warnings as errors, into docs/_build/html
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
CORE   := $(VENV)/.installed-core
FULL   := $(VENV)/.installed-full
# torch's wheel on PyPI for Linux is the CUDA build (several GB). For a CPU-only one on your machine:
#   make test TORCH_INDEX=https://download.pytorch.org/whl/cpu
TORCH_INDEX ?=

.PHONY: demo test docs bench reproduce train train-sarl train-sarl-crossings train-sarl-random clean venv

$(CORE): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e .
	touch $(CORE)

$(FULL): $(CORE)
	# torch first, pinned (and from TORCH_INDEX if given), so that nothing later pulls another build
	$(PY) -m pip install --quiet $(if $(TORCH_INDEX),--index-url $(TORCH_INDEX)) "torch==2.13.0"
	$(PY) -m pip install --quiet -e ".[rl,test,docs]"
	touch $(FULL)

venv: $(FULL)

demo: $(CORE)  ## the main job: baseline evaluation on the default suite (no torch needed)
	$(PY) scripts/evaluate.py --suite default --out results/default

test: $(FULL)
	$(PY) -m pytest -q -n 2

docs: $(FULL)  ## the site: every page, the docstrings, internal links checked (-W: a warning fails)
	$(PY) -m sphinx -W -b html docs docs/_build/html

# mealpy 3.0.3 pins numpy <= 1.26: the library comparison gets its own venv, the env's speed is
# measured in the main one (numpy 2, what a fresh install gets)
BENCH_VENV := .venv-bench
bench: $(CORE)
	$(PY) scripts/bench_env.py
	$(PY) scripts/bench_families.py
	$(PY) -m pip install --quiet -e ".[sensors-bench]"
	$(PY) scripts/bench_sensors.py
	test -x $(BENCH_VENV)/bin/python || $(PYTHON) -m venv $(BENCH_VENV)
	$(BENCH_VENV)/bin/python -m pip install --quiet -e ".[bench]"
	$(BENCH_VENV)/bin/python scripts/bench_planners.py

train: $(FULL)  ## retrain the shipped PPO policy (~35 min on 2 cores) and copy it to agents/models/
	$(PY) scripts/train_rl.py --total-timesteps 4000000 --seed 0 --out runs/ppo --ship best

train-sarl: $(FULL)  ## retrain SARL on CrowdNav's circle crossing (<= 58 min wall clock) -> agents/models/sarl_crowdnav.npz
	$(PY) scripts/train_sarl.py --setting crowdnav-no-robot-velocity --seed 0 --budget-minutes 58 --epsilon-decay 4000 --val-every 500 \
		--out runs/sarl_crowdnav

train-sarl-crossings: $(FULL)  ## retrain SARL on CrowdNav's circle and square crossings, taking turns (<= 58 min) -> agents/models/sarl_crowdnav_crossings.npz
	$(PY) scripts/train_sarl.py --setting crowdnav-no-robot-velocity --scenario crowdnav-circle-crossing,crowdnav-square-crossing --seed 0 --budget-minutes 58 \
		--epsilon-decay 4000 --val-every 500 --model-name sarl_crowdnav_crossings --out runs/sarl_crowdnav_crossings

train-sarl-random: $(FULL)  ## retrain SARL on random scenes, 8 bouncing obstacles, a Δd curriculum to 1.25 (<= 58 min) -> agents/models/sarl_random.npz
	nice -n 5 $(PY) scripts/train_sarl.py --setting random-no-robot-velocity --scenario random --delta-d 0.25 --curriculum-max 1.25 \
		--curriculum-episodes 1500 --val-delta-d 0.25,0.5,1 --val-episodes 50 --teacher astar-spacetime --teacher-kwargs '{}' \
		--seed 0 --budget-minutes 58 --rl-episodes 40000 --out runs/sarl_random

reproduce: $(CORE)
	$(PY) scripts/reproduce_paper.py --out results/paper

clean:
	rm -rf $(VENV) $(BENCH_VENV) results .pytest_cache docs/_build
