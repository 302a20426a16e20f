# Set-up and main entry points. Every target creates or reuses the local virtualenv.
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: demo test bench reproduce train clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	# CPU build of torch first, so nothing later pulls in a multi-GB CUDA build.
	$(PY) -m pip install --quiet "torch==2.13.0"
	$(PY) -m pip install --quiet -e ".[rl,test]"
	touch $(STAMP)

venv: $(STAMP)

demo: $(STAMP)  ## the main job: baseline evaluation on the default suite
	$(PY) scripts/evaluate.py --suite default --out results/default

test: $(STAMP)
	$(PY) -m pytest -q -n 2

bench: $(STAMP)
	$(PY) -m pip install --quiet -e ".[bench]"
	$(PY) scripts/bench_env.py
	$(PY) scripts/bench_planners.py

train: $(STAMP)  ## retrain the shipped PPO policy (~35 min on 2 cores) and copy it to agents/models/
	$(PY) scripts/train_rl.py --total-timesteps 4000000 --seed 0 --out runs/ppo --ship best

reproduce: $(STAMP)
	$(PY) scripts/reproduce_paper.py --out results/paper

clean:
	rm -rf $(VENV) results .pytest_cache
