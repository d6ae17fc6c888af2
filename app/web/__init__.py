"""What every page shares: templates, cookies, CSRF, sign-in dependencies, errors, the chart."""
