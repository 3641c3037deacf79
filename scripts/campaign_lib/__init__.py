"""scripts/campaign: a study's plan run in installments within a time budget, its results
stored with their provenance (docs/campaign.md). One concept per module: plan, engine,
golden, store, workdir, state, runner, assemble, cli."""
