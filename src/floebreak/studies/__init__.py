"""Parameter studies and Monte Carlo ensembles."""
