"""Languages: the ones trikecert speaks, the one a request is answered in, and its catalogs.

English is the source language (every message id is its English text) and the legally binding one;
Hausa, Yoruba, Igbo and Nigerian Pidgin are translations (app/i18n/locale/, docs/translations.md).
"""
