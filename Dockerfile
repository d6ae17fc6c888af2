# trikecert: slim Python base, non-root user, `trikecert serve`; workers from TRIKECERT_WORKERS.
FROM python:3.11-slim-bookworm

ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    TRIKECERT_WORKERS=2

WORKDIR /srv/trikecert
COPY pyproject.toml README.md alembic.ini ./
COPY app ./app
COPY migrations ./migrations
COPY templates ./templates
RUN pip install . && useradd --system --uid 10001 --home-dir /srv/trikecert trikecert \
    && install -d -m 0700 -o trikecert /var/lib/trikecert/keys
USER trikecert

EXPOSE 8000
HEALTHCHECK --interval=10s --timeout=3s --retries=5 \
    CMD python -c "import urllib.request,sys; sys.exit(urllib.request.urlopen('http://127.0.0.1:8000/healthz').status != 200)"
CMD ["sh", "-c", "exec trikecert serve --no-migrate --host 0.0.0.0 --port 8000 --workers ${TRIKECERT_WORKERS}"]
