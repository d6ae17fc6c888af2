"""Trust: the signing keys (file, PKCS#11 token, configuration), the signed QR payload, its verification."""
