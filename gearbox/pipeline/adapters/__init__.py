"""Stage functions: thin adapters from a (restricted) scene and upstream results to
the stage modules' own entry points. Each imports its stage module when it runs."""
