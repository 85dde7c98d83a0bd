"""Options and choices.

The enumerated choices, the validated options objects a fit, a Pareto run or a simulation carries
whole from the API or the command line into its result, their value checks and the resource caps.
Free of numpy, so the command line builds them before it loads the numerics.
"""
