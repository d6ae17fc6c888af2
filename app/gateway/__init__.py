"""Feature phones: check a keke by USSD or SMS, ask for reminders, stop them. The core (check, menu,
keywords) knows no provider; africastalking.py speaks Africa's Talking's callbacks and send API."""
